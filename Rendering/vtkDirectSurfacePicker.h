/**
 * @class   vtkDirectSurfacePicker
 * @brief   A vtkCellPicker that picks a vtkDirectSurfaceMapper's exact surface
 *
 * vtkCellPicker intersects the cells of an actor's input, so on a vtkDirectSurfaceMapper's actor
 * it would find the mesh's faces, not the isosurface (its dataset test is not the mapper's to
 * change). This picker is a vtkCellPicker in every respect except that on such actors it asks
 * the mapper (vtkDirectSurfaceMapper::PickSegment): the pick position is the exact crossing of
 * the iso-surface inside the clipping planes (to rounding), the pick normal the field's exact
 * gradient direction, CellId, PCoords (tetrahedra; hexahedra and wedges have none: 0), DataSet
 * and FlatBlockIndex those of the hit cell, PointId its node nearest the hit. GetLastPick holds
 * the mapper's full answer (every point array interpolated at the hit). Other props are picked
 * as vtkCellPicker picks them, and the nearest of all wins.
 *
 * @code
 * vtkNew<vtkDirectSurfacePicker> picker;
 * interactor->SetPicker(picker);       // or picker->Pick(x, y, 0, renderer)
 * @endcode
 *
 * vtkPropPicker, which asks hardware selection for the prop and the depth buffer for the point,
 * gives the point to the depth buffer's precision.
 *
 * @sa vtkDirectSurfaceMapper vtkDirectSurfacePick vtkCellPicker
 */
#ifndef vtkDirectSurfacePicker_h
#define vtkDirectSurfacePicker_h

#include "TetDSRRenderingModule.h" // for export macro
#include "vtkCellPicker.h"
#include "vtkNew.h" // for vtkNew

class vtkDirectSurfacePick;

class TETDSRRENDERING_EXPORT vtkDirectSurfacePicker : public vtkCellPicker
{
public:
  static vtkDirectSurfacePicker* New();
  vtkTypeMacro(vtkDirectSurfacePicker, vtkCellPicker);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The mapper's answer for the last pick that hit a Direct Surface (Hit false otherwise).
  vtkDirectSurfacePick* GetLastPick();

protected:
  vtkDirectSurfacePicker();
  ~vtkDirectSurfacePicker() override;

  void Initialize() override;
  double IntersectWithLine(const double p1[3], const double p2[3], double tol,
    vtkAssemblyPath* path, vtkProp3D* prop, vtkAbstractMapper3D* mapper) override;

private:
  vtkDirectSurfacePicker(const vtkDirectSurfacePicker&) = delete;
  void operator=(const vtkDirectSurfacePicker&) = delete;

  vtkNew<vtkDirectSurfacePick> LastPick;
  vtkNew<vtkDirectSurfacePick> Candidate;
};

#endif
