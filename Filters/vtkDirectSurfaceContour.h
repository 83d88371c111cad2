/**
 * @class   vtkDirectSurfaceContour
 * @brief   the exact isosurface of a higher-order finite-element field as a certified triangle surface
 *
 * vtkDirectSurfaceContour takes the same input as vtkDirectSurfaceRayCaster (a
 * vtkUnstructuredGrid of the tetrahedra, hexahedra, wedges and pyramids it reads, straight or
 * curved, with a point scalar field) and outputs the isosurfaces as a vtkPolyData of triangles
 * that is watertight and certified: every vertex is a root of the cell's own polynomial field
 * (not of a linear interpolation of nodal values), every triangle lies within DistanceBound of
 * the true surface (and the surface within DistanceBound of the triangles), and no piece of the
 * surface is missed, however small, including surfaces whose cells' nodal values all lie on one
 * side of the iso-value (where vtkContourFilter, which contours linear sub-cells, draws nothing).
 * The core subdivides each cell whose certified field range holds an iso-value until the
 * surface in each piece is one disc (see tetdsr/surface/ExactSurface.h and docs/how-it-works.md).
 *
 * Output:
 * - points (double) and triangles, each triangle's normal toward higher field values;
 * - point data `Normals` (the active normals): the exact unit normal, the field's gradient, at
 *   each vertex; and every numeric point array of the input, under its own name (an unnamed one
 *   as `array <its index in the input's point data>`) and with its components, interpolated at
 *   the vertices with the cell's own shape functions (as doubles; arrays that are not numeric,
 *   such as vtkStringArray, are left out);
 * - cell data `vtkOriginalCellIds` (vtkIdTypeArray: the input cell each triangle lies in) and
 *   `IsoValue` (double: the iso-value of its surface);
 * - field data, one tuple per iso-value in SetValue's order: `IsoValues` and, with
 *   ComputeIntegrals on, `Area`, `AreaError` (of the curved surface), `Volume`, `VolumeError` (of
 *   the valid cells' region where the field >= the iso-value), `FlatArea` (the triangles' own
 *   area) and, per numeric input point array, `<name> Integral` and `<name> IntegralError` (the
 *   array's integral over the curved surface, one component per component of the array); one
 *   tuple each: `DistanceBound` (the absolute tolerance asked), `LargestCertifiedBound` (the largest
 *   certified distance of any piece drawn), `Subcells` (tetrahedra examined),
 *   `UnresolvedSubcells` (left uncertified after tetdsr::kMaxSurfaceLevels bisections, drawn as
 *   marching tetrahedra would; warned of), `SizeCertifiedSubcells` (certified by their size alone:
 *   the surface in them is within the bound, its topology at a scale below the bound is not
 *   certified), `BoundaryEdges` (edges used by one triangle: where the
 *   surface meets the mesh's boundary) and `NonManifoldEdges` (edges used by more than two: none
 *   on a certified surface).
 *
 * The errors are estimates (see tetdsr/surface/ExactSurface.h), not bounds. Every check and every
 * message is the core's: settings it refuses, and inputs of which nothing can be made, give an
 * error and an empty output; cells it skips and pieces it cannot certify give warnings with
 * their counts.
 *
 * The prepared mesh (cell validation) is kept between executions while the input's mesh and the
 * field array do not change, as vtkDirectSurfaceRayCaster's is.
 *
 * @warning Distributed input (ParaView's server, pvbatch under MPI): each process outputs the
 * surface of its own piece, and its field data hold its own piece's integrals; add them over the
 * processes for the whole mesh's.
 *
 * @sa vtkDirectSurfaceRayCaster vtkContourFilter
 */
#ifndef vtkDirectSurfaceContour_h
#define vtkDirectSurfaceContour_h

#include "TetDSRFiltersModule.h" // For export macro
#include "vtkNew.h"              // For vtkNew
#include "vtkPolyDataAlgorithm.h"

#include <memory> // For std::unique_ptr

class vtkContourValues;

class TETDSRFILTERS_EXPORT vtkDirectSurfaceContour : public vtkPolyDataAlgorithm
{
public:
  static vtkDirectSurfaceContour* New();
  vtkTypeMacro(vtkDirectSurfaceContour, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Iso-values, with vtkContourFilter's API. Default: one value, 0 (as vtkContourFilter).
   */
  void SetValue(int i, double value);
  double GetValue(int i);
  void SetNumberOfContours(int number);
  vtkIdType GetNumberOfContours();
  ///@}

  ///@{
  /**
   * Component of the field array (input array 0, chosen with SetInputArrayToProcess; default the
   * active point scalars). Default -1: the array must have one component.
   */
  vtkSetMacro(ArrayComponent, int);
  vtkGetMacro(ArrayComponent, int);
  ///@}

  ///@{
  /**
   * The distance bound: the largest distance from any triangle to the true surface (and back).
   * Tolerance is relative to the diagonal of the valid cells' bounding box (default
   * tetdsr::kDefaultRelativeTolerance, 1e-3); AbsoluteTolerance, in the mesh's units, replaces
   * it when above 0 (default 0). The core refuses negative or non-finite values, and both 0.
   */
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  vtkSetMacro(AbsoluteTolerance, double);
  vtkGetMacro(AbsoluteTolerance, double);
  ///@}

  ///@{
  /**
   * Compute the area, enclosed volume and point-array integrals of the curved surface (default
   * on).
   */
  vtkSetMacro(ComputeIntegrals, bool);
  vtkGetMacro(ComputeIntegrals, bool);
  vtkBooleanMacro(ComputeIntegrals, bool);
  ///@}

  ///@{
  /**
   * Threads; 0 (default) uses all cores. When the vtkSMPTools backend is Sequential and the
   * VTK_SMP_BACKEND_IN_USE environment variable is unset, the STDThread backend is used.
   */
  virtual void SetNumberOfThreads(int threads);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * After an update with ComputeIntegrals on: the area of the curved surface of the i-th
   * iso-value (SetValue's numbering), the volume of the valid cells' region where the field is
   * at least that iso-value, and estimates of their errors. NaN for an i out of range, or when
   * the integrals were not computed.
   */
  double GetArea(int i);
  double GetAreaError(int i);
  double GetVolume(int i);
  double GetVolumeError(int i);
  ///@}

  /**
   * After an update: the absolute distance bound the surface was made with (0 before).
   */
  vtkGetMacro(DistanceBound, double);

  /**
   * After an update: the pieces left uncertified after the most bisections (0 on a certified
   * surface).
   */
  vtkGetMacro(UnresolvedSubcells, vtkIdType);

  /**
   * Modification time including the iso-values.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkDirectSurfaceContour();
  ~vtkDirectSurfaceContour() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  vtkNew<vtkContourValues> ContourValues;
  int ArrayComponent = -1;
  double Tolerance; // tetdsr::kDefaultRelativeTolerance (the constructor sets it from the core)
  double AbsoluteTolerance = 0.0;
  bool ComputeIntegrals = true;
  int NumberOfThreads = 0;

  // The last update's results (cleared when it fails; the integrals are kept with the cache).
  double DistanceBound = 0.0;
  vtkIdType UnresolvedSubcells = 0;

private:
  vtkDirectSurfaceContour(const vtkDirectSurfaceContour&) = delete;
  void operator=(const vtkDirectSurfaceContour&) = delete;

  struct Cache;
  std::unique_ptr<Cache> Prepared;
};

#endif
