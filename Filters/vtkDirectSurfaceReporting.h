// How every VTK face of TetDSR (the filter vtkDirectSurfaceRayCaster and the mapper
// vtkDirectSurfaceMapper) passes the core's messages on: written once, so that the faces report
// the same sentences the same way, as warnings and errors of the object that ran the core (its
// WarningEvent / ErrorEvent observers see them).
//
// Not wrapped for Python: a C++ helper of the TetDSR modules.
#ifndef vtkDirectSurfaceReporting_h
#define vtkDirectSurfaceReporting_h

#include "TetDSRFiltersModule.h" // for export macro

#include "tetdsr/common/Messages.h"

class vtkObject;

namespace tetdsr
{
namespace vtkadapter
{

/// Reports `messages` as `object`'s own (vtkWarningWithObjectMacro, vtkErrorWithObjectMacro):
/// the warnings first, then the errors, and empties them, so that a later report does not
/// repeat them.
TETDSRFILTERS_EXPORT void ReportMessages(vtkObject* object, Messages& messages);

} // namespace vtkadapter
} // namespace tetdsr

#endif
