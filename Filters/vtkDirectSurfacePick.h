/**
 * @class   vtkDirectSurfacePick
 * @brief   What a vtkDirectSurfaceMapper's exact surface shows at a point of the screen
 *
 * The result of vtkDirectSurfaceMapper::Pick (a display position) and PickSegment (a line in
 * the input's coordinates), which vtkDirectSurfacePicker uses: the nearest crossing of an
 * iso-surface (or of a clipping plane's cap) inside the clipping planes, as a still frame draws
 * it. Position is exact to rounding (the ray's root of the field's polynomial), not a face of the
 * mesh or a depth-buffer read; Normal is along the field's exact gradient (towards increasing
 * field), the plane's normal on a cap.
 *
 * @sa vtkDirectSurfaceMapper vtkDirectSurfacePicker
 */
#ifndef vtkDirectSurfacePick_h
#define vtkDirectSurfacePick_h

#include "TetDSRFiltersModule.h" // for export macro
#include "vtkNew.h"                // for vtkNew
#include "vtkObject.h"
#include "vtkDataSet.h"       // for vtkSmartPointer<vtkDataSet>
#include "vtkPointData.h"     // for vtkNew<vtkPointData>
#include "vtkSmartPointer.h"  // for vtkSmartPointer


class TETDSRFILTERS_EXPORT vtkDirectSurfacePick : public vtkObject
{
public:
  static vtkDirectSurfacePick* New();
  vtkTypeMacro(vtkDirectSurfacePick, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Back to "nothing picked".
  void Initialize();
  /// A copy of another pick (its point data copied too).
  void DeepCopyFrom(vtkDirectSurfacePick* other);

  /// Whether the surface (or a cap) was hit.
  vtkGetMacro(Hit, bool);
  /// The hit in world coordinates (through the actor's matrix) and in the input's.
  vtkGetVector3Macro(Position, double);
  vtkGetVector3Macro(MapperPosition, double);
  /// Unit normal in world coordinates and in the input's.
  vtkGetVector3Macro(Normal, double);
  vtkGetVector3Macro(MapperNormal, double);
  /// The input's cell (of the block FlatBlockIndex of a composite input; -1 otherwise).
  vtkGetMacro(CellId, vtkIdType);
  vtkGetMacro(FlatBlockIndex, vtkIdType);
  /// The picked grid (the block, for a composite input).
  vtkDataSet* GetDataSet() { return this->DataSet; }
  /// VTK's parametric coordinates of the hit in its cell (tetrahedra: vertex 0 at the origin,
  /// vertices 1, 2, 3 at r, s, t = 1; hexahedra and VTK_PYRAMID: VTK's (r, s, t)), when
  /// HasParametricCoordinates: not in a mesh with wedges (straight ones are rendered as
  /// tetrahedra, and that mesh's cells are then not the input's own).
  vtkGetMacro(HasParametricCoordinates, bool);
  vtkGetVector3Macro(ParametricCoordinates, double);
  /// The iso-value crossed (its index, as given to SetValue), -1 on a cap; the clipping plane of
  /// a cap (its index), -1 otherwise.
  vtkGetMacro(IsoValueIndex, int);
  vtkGetMacro(ClippingPlaneId, int);
  /// The contoured field interpolated at the hit (the iso-value, to rounding, on a surface).
  vtkGetMacro(Value, double);
  /// The distance from the ray's start in the input's coordinates (a segment's fraction for
  /// PickSegment).
  vtkGetMacro(RayParameter, double);
  /// Every point array of the picked grid interpolated at the hit with the cell's shape
  /// functions: one tuple each, named as in the grid.
  vtkPointData* GetPointData() { return this->PointData; }

  ///@{
  /// Set by the mapper.
  void SetHit(bool hit) { this->Hit = hit; }
  vtkSetVector3Macro(Position, double);
  vtkSetVector3Macro(MapperPosition, double);
  vtkSetVector3Macro(Normal, double);
  vtkSetVector3Macro(MapperNormal, double);
  vtkSetMacro(CellId, vtkIdType);
  vtkSetMacro(FlatBlockIndex, vtkIdType);
  void SetDataSet(vtkDataSet* dataSet);
  vtkSetMacro(HasParametricCoordinates, bool);
  vtkSetVector3Macro(ParametricCoordinates, double);
  vtkSetMacro(IsoValueIndex, int);
  vtkSetMacro(ClippingPlaneId, int);
  vtkSetMacro(Value, double);
  vtkSetMacro(RayParameter, double);
  ///@}

protected:
  vtkDirectSurfacePick();
  ~vtkDirectSurfacePick() override;

  bool Hit = false;
  double Position[3] = { 0.0, 0.0, 0.0 };
  double MapperPosition[3] = { 0.0, 0.0, 0.0 };
  double Normal[3] = { 0.0, 0.0, 0.0 };
  double MapperNormal[3] = { 0.0, 0.0, 0.0 };
  vtkIdType CellId = -1;
  vtkIdType FlatBlockIndex = -1;
  bool HasParametricCoordinates = false;
  double ParametricCoordinates[3] = { 0.0, 0.0, 0.0 };
  int IsoValueIndex = -1;
  int ClippingPlaneId = -1;
  double Value = 0.0;
  double RayParameter = 0.0;
  vtkSmartPointer<vtkDataSet> DataSet;
  vtkNew<vtkPointData> PointData;

private:
  vtkDirectSurfacePick(const vtkDirectSurfacePick&) = delete;
  void operator=(const vtkDirectSurfacePick&) = delete;
};

#endif
