#include "vtkDirectSurfaceReporting.h"

#include "vtkObject.h"

#include <string>

namespace tetdsr
{
namespace vtkadapter
{

void ReportMessages(vtkObject* object, Messages& messages)
{
  for (const std::string& text : messages.warnings)
  {
    vtkWarningWithObjectMacro(object, << text);
  }
  for (const std::string& text : messages.errors)
  {
    vtkErrorWithObjectMacro(object, << text);
  }
  messages = Messages();
}

} // namespace vtkadapter
} // namespace tetdsr
