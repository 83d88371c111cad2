/**
 * @class   vtkDirectSurfaceRayCaster
 * @brief   ray cast the exact isosurface of a higher-order finite-element field into an image
 *
 * vtkDirectSurfaceRayCaster renders isosurfaces of a point scalar field on a
 * vtkUnstructuredGrid of tetrahedra (VTK_TETRA, VTK_QUADRATIC_TETRA, and
 * VTK_LAGRANGE_TETRAHEDRON / VTK_BEZIER_TETRAHEDRON of orders 1 to 4), hexahedra (VTK_HEXAHEDRON,
 * VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
 * VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON / VTK_BEZIER_HEXAHEDRON of orders 1 to 4),
 * wedges (VTK_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE,
 * VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE / VTK_BEZIER_WEDGE of orders 1 to 4) and
 * pyramids (VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID), straight or curved,
 * each solved in its own reference space, mixed freely, by direct
 * surface rendering (Simpson, "An efficient, high quality method for rendering irregular,
 * quadratic, volume data"): one ray per pixel, the field along the ray inside each straight cell
 * taken exactly (in closed form as a quadratic for order 2, its first root with the stable
 * quadratic formula; for orders 3 and 4 in Bernstein form, its first root isolated by sign
 * changes and refined to rounding), the normal from the analytic gradient. Cells are pruned by rigorous Bernstein bounds of
 * the field, so no cell whose field reaches an iso-value is ever skipped (unlike
 * vtkContourFilter, which contours 8 linear sub-tets per cell and misses surfaces that
 * do not straddle nodal values).
 *
 * The output is a vtkImageData of ImageSize[0] x ImageSize[1] x 1 points with point arrays
 * - `Colors` (unsigned char RGBA, active scalars; background (0,0,0,0)),
 * - `Depth` (double; distance from the camera position along the unit ray in perspective,
 *   from the camera plane in parallel projection; +inf on misses),
 * - `Normals` (double x3; unit field gradient, pointing to increasing field, or the normal of
 *   the chosen NormalMode; 0 on misses),
 * - `CellId` (vtkIdType; input cell hit, -1 on misses),
 * - `ColorValues` (double; only when colouring by an array or capping a cut: the value that was
 *   colour-mapped at the nearest surface or cap, NaN elsewhere).
 * Depth, Normals, CellId and ColorValues describe the nearest surface (or cap); Colors composites
 * every translucent surface along the ray (not premultiplied; alpha is the total opacity).
 * Pixel (i, j), point id i + j*width, is the ray through the pixel centre, j = 0 at the bottom.
 *
 * Each setting's default, range and check are its row of the core's settings table (shared with
 * the Python filter and the ParaView plugins): numbers are clamped into their range (NaN is
 * refused with an error), enumerations and counts are clamped with a warning naming the value
 * used, vectors with a NaN or Inf are refused with an error.
 *
 * The closed form above is that of a straight-sided cell; curved cells are rendered exactly too
 * (see the warning below). VTK_TETRA cells are rendered as exact (linear) quadratics; rational
 * Bezier cells (RationalWeights that differ within a cell), Lagrange and Bezier tetrahedra of
 * order above 4, other cell types, cells of zero volume or with repeated node ids, and cells with NaN/Inf values or
 * coordinates are skipped with a warning giving their count. Inverted cells are rendered like
 * positive ones.
 *
 * Preprocessing (cell validation) is cached against the input's and the scalar array's
 * modification times, and the acceleration structure (the cells that can hold one of the
 * iso-values, with a hierarchy over them) against the iso-values: changing the camera or the
 * shading re-renders without rebuilding, changing the iso-values rebuilds only the latter.
 *
 * Distributed input (a vtkMultiProcessController with several processes, e.g. ParaView's server
 * or pvbatch under MPI): each process casts its own piece of the mesh into the whole image, and
 * the images are composited by depth, so that each process outputs its requested extent of the
 * picture the whole mesh gives (the filter produces sub-extents: ParaView asks each process for a
 * block of the image). Every process must execute the filter. Per pixel the nearest process's
 * Depth, Normals, CellId and ColorValues are kept, and Colors composite every process's
 * crossings sorted along the ray, as one process holding every cell would (translucent surfaces
 * whose crossings interleave between the pieces included). CellId counts the cells of the processes'
 * pieces one after another in process order (the numbering of a .pvtu read whole).
 *
 * @warning Curved cells (a node off where the affine map of the vertices puts it by more than
 * rounding) are rendered exactly, as the image of the reference tet under their map of degree 2
 * to 4, by a subdivision
 * solver rather than the quadratic formula: slower, and a hit at a tangent or near-tangent root
 * is accepted without a certificate (NumberOfUncertifiedHits counts them); curved cells that fold
 * (tangled) are skipped with a warning. Distributed, two results are the serial ones only up to
 * where the pieces meet: DEPTH_BUFFER normals, differenced within each process's image (and the
 * colours shaded with them); and the default
 * camera, fitted to the union of the pieces' bounding boxes (each rounded outward to single
 * precision).
 *
 * @sa vtkContourFilter vtkCamera
 */
#ifndef vtkDirectSurfaceRayCaster_h
#define vtkDirectSurfaceRayCaster_h

#include "TetDSRFiltersModule.h" // For export macro
#include "vtkImageAlgorithm.h"
#include "vtkNew.h" // For vtkNew

#include <memory> // For std::unique_ptr
#include <vector> // For std::vector

class vtkCamera;
class vtkDataArray;
class vtkContourValues;
class vtkDirectSurfacePick;
class vtkMultiProcessController;
class vtkPlane;
class vtkPlaneCollection;
class vtkScalarsToColors;

class TETDSRFILTERS_EXPORT vtkDirectSurfaceRayCaster : public vtkImageAlgorithm
{
public:
  static vtkDirectSurfaceRayCaster* New();
  vtkTypeMacro(vtkDirectSurfaceRayCaster, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Iso-values, with vtkContourFilter's API. With several values a pixel shows the nearest
   * crossing of any of them. Default: one value, 0 (as vtkContourFilter).
   */
  void SetValue(int i, double value);
  double GetValue(int i);
  double* GetValues();
  void GetValues(double* contourValues);
  void SetNumberOfContours(int number);
  vtkIdType GetNumberOfContours();
  void GenerateValues(int numContours, double range[2]);
  void GenerateValues(int numContours, double rangeStart, double rangeEnd);
  ///@}

  ///@{
  /**
   * Camera: position, focal point, view up, view angle (vertical, degrees), parallel
   * projection and parallel scale are used (the clipping range is not: rays start at the camera).
   * A camera with an explicit projection matrix, an off-axis projection, a window centre, a view
   * shear or user or model transforms is refused with an error (vtkDirectSurfaceMapper draws
   * those). Default: none, meaning a camera that sees the whole mesh the way
   * vtkRenderer::ResetCamera places it (looking down -z, view up +y).
   */
  void SetCamera(vtkCamera* camera);
  vtkGetObjectMacro(Camera, vtkCamera);
  ///@}

  ///@{
  /**
   * Output image width and height in pixels. Default 512 x 512.
   */
  vtkSetVector2Macro(ImageSize, int);
  vtkGetVector2Macro(ImageSize, int);
  ///@}

  ///@{
  /**
   * Component of the scalar array to render. Default -1: the array must have one component.
   */
  vtkSetMacro(ArrayComponent, int);
  vtkGetMacro(ArrayComponent, int);
  ///@}

  ///@{
  /**
   * Phong shading: surface colour (default white), ambient (0.1), diffuse (0.7),
   * specular (0.2) coefficients and specular power (30). The side facing the viewer is lit.
   * The coefficients are clamped to [0, 1], the power to [0, 128]; NaN is refused with an error,
   * and so is a colour with a NaN or infinite component.
   */
  virtual void SetSurfaceColor(double red, double green, double blue);
  void SetSurfaceColor(const double color[3]) { this->SetSurfaceColor(color[0], color[1], color[2]); }
  vtkGetVector3Macro(SurfaceColor, double);
  virtual void SetAmbient(double ambient);
  vtkGetMacro(Ambient, double);
  virtual void SetDiffuse(double diffuse);
  vtkGetMacro(Diffuse, double);
  virtual void SetSpecular(double specular);
  vtkGetMacro(Specular, double);
  virtual void SetSpecularPower(double power);
  vtkGetMacro(SpecularPower, double);
  ///@}

  ///@{
  /**
   * The point light: at the camera position when LightAtCamera is on (default), else at
   * LightPosition (world coordinates, default (0, 0, 1); a NaN or infinite coordinate is refused
   * with an error).
   */
  vtkSetMacro(LightAtCamera, bool);
  vtkGetMacro(LightAtCamera, bool);
  vtkBooleanMacro(LightAtCamera, bool);
  virtual void SetLightPosition(double x, double y, double z);
  void SetLightPosition(const double position[3])
  {
    this->SetLightPosition(position[0], position[1], position[2]);
  }
  vtkGetVector3Macro(LightPosition, double);
  ///@}

  /**
   * How surface normals are obtained (the paper's section 2.5, and the exact one).
   */
  enum NormalModes
  {
    /// The analytic gradient of the hit cell's quadratic (default).
    EXACT_GRADIENT = 0,
    /// Central differences of six samples at +-CentralDifferenceStep, each evaluated in the cell
    /// that contains it (point location through the acceleration structure).
    CENTRAL_DIFFERENCES = 1,
    /// Gradients at the nodes (mean of the exact gradients of the cells around each node,
    /// computed once per mesh and array) interpolated with the cell's own shape functions.
    NODAL_INTERPOLATION = 2,
    /// Normals from the depth image's differences (the paper's "Z-buffer" shading).
    DEPTH_BUFFER = 3
  };

  ///@{
  /**
   * The normal scheme (default EXACT_GRADIENT) and, for CENTRAL_DIFFERENCES, the step as a
   * fraction of the hit cell's longest edge (default 1e-3). The `Normals` output holds the
   * normals used for shading: along the gradient for the first three modes, towards the viewer
   * for DEPTH_BUFFER.
   */
  virtual void SetNormalMode(int mode);
  vtkGetMacro(NormalMode, int);
  /// Clamped to [1e-12, 1]; NaN is refused with an error.
  virtual void SetCentralDifferenceStep(double step);
  vtkGetMacro(CentralDifferenceStep, double);
  ///@}

  ///@{
  /**
   * Colour and opacity of the surface of the i-th iso-value (in SetValue's numbering). A value
   * without a colour uses SurfaceColor; without an opacity it is opaque (1). With any opacity
   * below 1 every crossing along a ray is composited front to back (nested translucent
   * surfaces), up to 64 crossings per ray. Colouring by an array replaces the colours, not the
   * opacities.
   */
  void SetIsoValueColor(int i, double red, double green, double blue);
  void GetIsoValueColor(int i, double color[3]);
  void RemoveAllIsoValueColors();
  void SetIsoValueOpacity(int i, double opacity);
  double GetIsoValueOpacity(int i);
  void RemoveAllIsoValueOpacities();
  ///@}

  ///@{
  /**
   * Colour the surfaces by a second point array (default off), interpolated at each hit with
   * the hit cell's own shape functions (of its order) and mapped through LookupTable. The array is input
   * array 1: SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, name).
   * ColorArrayComponent picks a component; -1 (default) is the magnitude of the interpolated
   * vector (for one component, the value itself). ColorRange is the range of values spread over
   * the lookup table; when ColorRange[0] > ColorRange[1] (default (0, -1)) the array's range is
   * used.
   */
  vtkSetMacro(ColorByArray, bool);
  vtkGetMacro(ColorByArray, bool);
  vtkBooleanMacro(ColorByArray, bool);
  virtual void SetColorArrayComponent(int component);
  vtkGetMacro(ColorArrayComponent, int);
  vtkSetVector2Macro(ColorRange, double);
  vtkGetVector2Macro(ColorRange, double);
  ///@}

  /**
   * Built-in colour maps, used when no LookupTable is set.
   */
  enum ColorMaps
  {
    COOL_TO_WARM = 0, ///< diverging blue - white - red (default)
    RAINBOW = 1,      ///< blue - cyan - green - yellow - red (HSV)
    GRAYSCALE = 2,    ///< black - white
    BLACK_BODY = 3    ///< black - red - yellow - white
  };

  ///@{
  /**
   * The colour map for ColorByArray and for caps: LookupTable if set (its own range is
   * stretched over ColorRange), else the built-in ColorMap (default COOL_TO_WARM).
   */
  virtual void SetLookupTable(vtkScalarsToColors* lookupTable);
  vtkGetObjectMacro(LookupTable, vtkScalarsToColors);
  virtual void SetColorMap(int which);
  vtkGetMacro(ColorMap, int);
  ///@}

  /**
   * At most this many clipping planes.
   */
  static constexpr int MaximumNumberOfClippingPlanes = 6;

  ///@{
  /**
   * Clipping planes (default none): each keeps the side its normal points to, as vtkMapper's
   * clipping planes do. Rays start and end where the planes allow, so the surfaces inside are
   * seen through the cut. At most MaximumNumberOfClippingPlanes.
   */
  void AddClippingPlane(vtkPlane* plane);
  void RemoveAllClippingPlanes();
  virtual void SetClippingPlanes(vtkPlaneCollection* planes);
  vtkGetObjectMacro(ClippingPlanes, vtkPlaneCollection);
  ///@}

  /**
   * Which part of a cut is capped.
   */
  enum CappingModes
  {
    /// No cap: the cut is open (default).
    NO_CAP = 0,
    /// Cap where the field on the clipping plane is below the largest iso-value (inside the
    /// surfaces of a field that grows outward, such as a distance).
    CAP_BELOW_ISO_VALUE = 1,
    /// Cap where the field on the clipping plane is above the smallest iso-value.
    CAP_ABOVE_ISO_VALUE = 2
  };

  ///@{
  /**
   * Capping of the cut (default NO_CAP): where a ray enters the kept region through a clipping
   * plane inside the mesh and the field there is on the capped side, the pixel shows the plane,
   * coloured through the colour map by the colour array when ColorByArray is on, else by the
   * field (ColorRange, if automatic, is then the field's range).
   */
  virtual void SetCapping(int mode);
  vtkGetMacro(Capping, int);
  ///@}

  /**
   * Transverse-cell tests: which cells are searched for an iso-value.
   */
  enum TransverseTestModes
  {
    /// The Bernstein coefficients' range: a guaranteed bound, no cell is ever missed (default).
    BERNSTEIN_BOUND = 0,
    /// The paper's heuristic: the nodal range widened by NodalRangeWidening on each side. Not a
    /// bound: kept to show where it leaves holes.
    WIDENED_NODAL_RANGE = 1
  };

  ///@{
  /**
   * The transverse-cell test (default BERNSTEIN_BOUND) and, for WIDENED_NODAL_RANGE, the
   * widening as a fraction of the nodal range (default 0.25, the paper's 25%). Changing either
   * rebuilds the acceleration structure.
   */
  virtual void SetTransverseTest(int mode);
  vtkGetMacro(TransverseTest, int);
  /// Clamped to [0, VTK_DOUBLE_MAX]; NaN is refused with an error.
  virtual void SetNodalRangeWidening(double widening);
  vtkGetMacro(NodalRangeWidening, double);
  ///@}

  ///@{
  /**
   * Threads for ray casting; 0 (default) uses all cores. The image is identical bit for bit
   * whatever the number of threads. When the vtkSMPTools backend is Sequential and the
   * VTK_SMP_BACKEND_IN_USE environment variable is unset, the STDThread backend is used.
   */
  virtual void SetNumberOfThreads(int threads);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * What the last preprocessing found: cells rendered, inverted (rendered), curved (rendered
   * as the isoparametric image of the reference cell), of order 3 or 4 (rendered: Lagrange and
   * Bezier tetrahedra of 20 and 35 nodes, hexahedra and wedges of order 3 or 4 per axis, and
   * VTK_TRIQUADRATIC_PYRAMID, of degree 3 along its axis in its reference cube), and
   * skipped for: tangled curved cells (the Jacobian
   * determinant changes sign inside), flat or needle-like shape or repeated node ids
   * (degenerate), NaN/Inf values or coordinates, node ids out of range, an unsupported cell
   * type, a number of ids that does not match the type or offsets out of order (malformed), a
   * Lagrange or Bezier tetrahedron of order above 4, a rational Bezier cell (weights that differ
   * within it), a longest edge outside [1e-100, 1e100] (out of scale). Ghost cells (cell
   * array vtkGhostType with the DUPLICATECELL or HIDDENCELL bit, as distributed writers and
   * ghost-cell generators leave them) are left out without a warning: the piece that owns one
   * draws it (NumberOfGhostCells counts them).
   */
  vtkGetMacro(NumberOfRenderedCells, vtkIdType);
  vtkGetMacro(NumberOfInvertedCells, vtkIdType);
  vtkGetMacro(NumberOfCurvedCells, vtkIdType);
  vtkGetMacro(NumberOfDegenerateCells, vtkIdType);
  vtkGetMacro(NumberOfTangledCells, vtkIdType);
  vtkGetMacro(NumberOfNonFiniteCells, vtkIdType);
  vtkGetMacro(NumberOfInvalidIdCells, vtkIdType);
  vtkGetMacro(NumberOfUnsupportedCells, vtkIdType);
  vtkGetMacro(NumberOfMalformedCells, vtkIdType);
  vtkGetMacro(NumberOfOrderTooHighCells, vtkIdType);
  vtkGetMacro(NumberOfRationalCells, vtkIdType);
  vtkGetMacro(NumberOfHigherOrderCells, vtkIdType);
  vtkGetMacro(NumberOfOutOfScaleCells, vtkIdType);
  vtkGetMacro(NumberOfGhostCells, vtkIdType);
  ///@}

  /**
   * Hits in curved cells, in the last image, that the solver accepted at its subdivision limit
   * without a Krawczyk certificate (tangent or near-tangent roots; every other hit in a curved
   * cell is certified). Counts the crossings behind translucent surfaces too, not only the
   * pixels' nearest hits.
   */
  vtkGetMacro(NumberOfUncertifiedHits, vtkIdType);

  /**
   * The exact surface at a position of the last output image: pixel (i, j) covers
   * [i, i + 1) x [j, j + 1), and (i + 0.5, j + 0.5) gives exactly the hit that pixel shows. With
   * the last execution's camera, iso-values and clipping planes (a cap included), it fills
   * `result` (position, cell, parametric coordinates, the field and every point array
   * interpolated at the hit, the exact normal: vtkDirectSurfacePick) and returns whether
   * anything was hit; false before an execution that cast an image, or after the input changed.
   * Distributed, it sees this process's piece only.
   */
  bool Pick(double x, double y, vtkDirectSurfacePick* result);

  ///@{
  /**
   * The processes the input is distributed over (default: the global controller, if any). With
   * one process, or none, the whole input is rendered here.
   */
  virtual void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /**
   * Bytes the filter keeps between executions for the current mesh and array (validation
   * results, the acceleration structure of the current iso-values, and copies of input arrays
   * VTK stores in another layout). 0 before the first execution.
   */
  vtkIdType GetPreprocessedBytes();

  /**
   * Modification time including the iso-values, the camera, the lookup table and the clipping
   * planes.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkDirectSurfaceRayCaster();
  ~vtkDirectSurfaceRayCaster() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  vtkNew<vtkContourValues> ContourValues;
  vtkCamera* Camera = nullptr;
  // The settings' defaults are the core's settings table's (set by the constructor).
  int ImageSize[2]{};
  int ArrayComponent{};
  double SurfaceColor[3]{};
  double Ambient{};
  double Diffuse{};
  double Specular{};
  double SpecularPower{};
  bool LightAtCamera{};
  double LightPosition[3]{};
  int NumberOfThreads{};
  int NormalMode{};
  double CentralDifferenceStep{};
  int TransverseTest{};
  double NodalRangeWidening{};
  bool ColorByArray{};
  int ColorArrayComponent{};
  double ColorRange[2]{};
  vtkScalarsToColors* LookupTable = nullptr;
  int ColorMap{};
  vtkPlaneCollection* ClippingPlanes = nullptr;
  int Capping{};
  vtkMultiProcessController* Controller = nullptr;

  vtkIdType NumberOfRenderedCells = 0;
  vtkIdType NumberOfInvertedCells = 0;
  vtkIdType NumberOfCurvedCells = 0;
  vtkIdType NumberOfDegenerateCells = 0;
  vtkIdType NumberOfTangledCells = 0;
  vtkIdType NumberOfUncertifiedHits = 0;
  vtkIdType NumberOfNonFiniteCells = 0;
  vtkIdType NumberOfInvalidIdCells = 0;
  vtkIdType NumberOfUnsupportedCells = 0;
  vtkIdType NumberOfMalformedCells = 0;
  vtkIdType NumberOfOrderTooHighCells = 0;
  vtkIdType NumberOfRationalCells = 0;
  vtkIdType NumberOfHigherOrderCells = 0;
  vtkIdType NumberOfGhostCells = 0;
  vtkIdType NumberOfOutOfScaleCells = 0;

private:
  vtkDirectSurfaceRayCaster(const vtkDirectSurfaceRayCaster&) = delete;
  void operator=(const vtkDirectSurfaceRayCaster&) = delete;

  /// Input array `index` (0: the field, 1: the colour array), or null after an error naming it.
  vtkDataArray* GetPointArray(int index, vtkInformationVector** inputVector, int& association);

  ///@{
  /**
   * RequestData's steps. Distributed, each is collective: it returns the same on every process
   * (false after reporting why on the processes that found a problem), so that all stop together.
   */
  struct Execution;
  /// The field, the iso-values, the colour array and the clipping planes (a process with an
  /// empty piece checks only the settings).
  bool ChooseArraysAndSettings(vtkInformationVector** inputVector, Execution& run);
  /// Validates the piece and builds its scene (once per mesh, array and transverse test), and
  /// counts its cells by what was found; warns of the cells skipped.
  bool PrepareScene(Execution& run);
  /// The user's camera, or one that sees every rendered cell of every piece (points no cell
  /// uses do not count).
  bool ChooseCamera(Execution& run);
  /// The core's shading, clipping and colour-mapping settings (the colour range, if automatic,
  /// over every piece).
  void ChooseShading(Execution& run);
  /// Casts the piece into this process's image; false, with a warning, when aborted.
  bool CastPiece(Execution& run);
  /// Scene cell indices back to input cell ids (distributed: the pieces' cells counted one after
  /// another in process order).
  void MapCellIds(const Execution& run);
  ///@}

  struct Cache;
  std::unique_ptr<Cache> Prepared;
};

#endif
