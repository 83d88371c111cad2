/**
 * @class   vtkDirectSurfaceRepresentation
 * @brief   ParaView's "Direct Surface" representation: exact isosurfaces of higher-order tetrahedra
 *
 * The representation behind "Direct Surface" in ParaView's representation drop-down for
 * unstructured grids and composite datasets of them. It hands its input, untouched, to a
 * vtkDirectSurfaceMapper, which ray casts the exact isosurfaces into the render view with exact
 * depth on every render. The data stays on the processes that hold it: the view is told the
 * representation needs distributed rendering, so in client-server mode and under MPI each
 * rendering rank casts its own piece and ParaView's compositing (IceT) merges the pieces by
 * depth.
 *
 * Everything is forwarded, nothing re-implemented: the field (SetContourBy), iso-values,
 * per-iso-value colours and opacities and clipping planes go to the mapper; colouring
 * (SetInputArrayToProcess with index 0, the ColorArrayName of ParaView's Color By, SetLookupTable,
 * SetMapScalars) to the mapper's standard colouring API; colour, opacity and lighting
 * coefficients to the actor's vtkProperty; the transform to the actor.
 *
 * Everything is checked, with the core's sentences (tetdsr/input/Settings.h, tetdsr/input/MeshInput.h), as
 * ParaView's properties are not (its Python sets any value, a domain only guides the panel):
 * a number outside its range is clamped with a warning and NaN refused with an error; a list
 * (ClipPlanes, IsoValueColors) that is not whole planes or colours is refused with an error; an
 * input that cannot show anything (empty, no finite point, a Contour By array that is missing or
 * has several components) is said so once per change of the input or of Contour By, and not
 * drawn (a renderer would cull an empty or non-finite actor before its mapper could say why);
 * a field constant at an iso-value is warned about.
 * With several processes a piece cannot tell the whole input's emptiness or range: only the
 * Contour By array's checks apply there.
 *
 * Translucent surfaces (an iso-value opacity or Opacity below 1) on several rendering processes
 * are composited by the representation itself: ParaView composites the processes' opaque images
 * by depth (IceT), then every process casts the crossings of the cells it holds and process 0
 * sorts them along each ray, drops those behind the composited depth, composites them front to
 * back and blends them over the composited frame (vtkDirectSurfaceMapper::
 * DrawTranslucentAcrossProcesses): the serial picture for any distribution of the cells, with no
 * cell moved. When another representation is translucent, ParaView composites in order (IceT
 * blends the processes' images without depth): the mapper then composites the processes' own
 * opaque depth itself, and opaque surfaces too are composited across the processes and drawn
 * over IceT's image (a warning says that translucent geometry in front of them is hidden then).
 * Other props' translucent geometry is composited by ParaView, not sorted with this surface.
 * Selection (Select Cells / Points On, hovering, Extract Selection) sees the surface: its actor is
 * registered with the view's hardware selector, and each process draws the cells its rays hit
 * (vtkDirectSurfaceMapper).
 *
 * @sa vtkDirectSurfaceMapper vtkDirectSurfaceRayCaster
 */
#ifndef vtkDirectSurfaceRepresentation_h
#define vtkDirectSurfaceRepresentation_h

#include "TetDSRParaViewRepresentationsModule.h" // For export macro
#include "vtkNew.h"                              // For vtkNew
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h" // For vtkSmartPointer

#include <string> // For std::string

class vtkActor;
class vtkDirectSurfaceMapper;
class vtkProperty;
class vtkRenderer;
class vtkScalarsToColors;

class TETDSRPARAVIEWREPRESENTATIONS_EXPORT vtkDirectSurfaceRepresentation
  : public vtkPVDataRepresentation
{
public:
  static vtkDirectSurfaceRepresentation* New();
  vtkTypeMacro(vtkDirectSurfaceRepresentation, vtkPVDataRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Hands the input to the view (REQUEST_UPDATE: the piece, its bounds, distributed rendering
   * required) and the delivered piece to the mapper (REQUEST_RENDER).
   */
  int ProcessViewRequest(vtkInformationRequestKey* request, vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  void SetVisibility(bool visible) override;

  ///@{
  /**
   * The field whose isosurfaces are rendered (a point array; the arguments of
   * SetInputArrayToProcess, of which only the association and name are used) and the
   * iso-values, forwarded to the mapper.
   */
  void SetContourBy(int index, int port, int connection, int fieldAssociation, const char* name);
  void SetContourValue(int i, double value);
  void SetNumberOfContours(int number);
  ///@}

  ///@{
  /**
   * Per-iso-value colours and opacities, and clipping planes given as a point and a normal,
   * forwarded to the mapper.
   */
  void SetIsoValueColor(int i, double red, double green, double blue);
  void RemoveAllIsoValueColors();
  void SetIsoValueOpacity(int i, double opacity);
  void RemoveAllIsoValueOpacities();
  void AddClipPlane(double x, double y, double z, double nx, double ny, double nz);
  void RemoveAllClipPlanes();
  ///@}

  ///@{
  /**
   * How many numbers IsoValueColors and ClipPlanes hold (vtkSIDirectSurfaceListProperty calls
   * these before the values): a count that is not whole colours (3) or planes (6) refuses the
   * list, with an error.
   */
  void SetIsoValueColorsCount(int count);
  void SetClipPlanesCount(int count);
  ///@}

  ///@{
  /**
   * Colouring, as ParaView's surface representation does it: index 0 is the colour array
   * (ParaView's ColorArrayName); an empty name turns scalar colouring off.
   */
  void SetInputArrayToProcess(
    int index, int port, int connection, int fieldAssociation, const char* name) override;
  using Superclass::SetInputArrayToProcess;
  void SetLookupTable(vtkScalarsToColors* lookupTable);
  /// 1: map the colour array through the lookup table; 0: use up to 4 components as colours.
  void SetMapScalars(int map);
  ///@}

  ///@{
  /**
   * Level of detail while the camera moves, forwarded to the mapper (its checks and clamping),
   * and the pixels per ray of the last frame it cast (on the first rendering process).
   */
  void SetAutoAdjustSampleDistances(int adjust);
  void SetInteractiveImageSampleDistance(double distance);
  double GetLastImageSampleDistance();
  ///@}

  ///@{
  /**
   * Forwarded to the actor's vtkProperty.
   */
  void SetOpacity(double opacity);
  void SetAmbientColor(double red, double green, double blue);
  void SetDiffuseColor(double red, double green, double blue);
  void SetSpecularColor(double red, double green, double blue);
  void SetAmbient(double ambient);
  void SetDiffuse(double diffuse);
  void SetSpecular(double specular);
  void SetSpecularPower(double power);
  ///@}

  ///@{
  /**
   * Forwarded to the actor.
   */
  void SetPosition(double x, double y, double z);
  void SetOrientation(double x, double y, double z);
  void SetOrigin(double x, double y, double z);
  void SetScale(double x, double y, double z);
  void SetUserTransform(const double matrix[16]);
  void SetPickable(int pickable);
  ///@}

  ///@{
  /**
   * The mapper and the actor (for tests and for what the properties do not cover).
   */
  vtkDirectSurfaceMapper* GetMapper() { return this->Mapper; }
  vtkActor* GetActor() { return this->Actor; }
  ///@}

protected:
  vtkDirectSurfaceRepresentation();
  ~vtkDirectSurfaceRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

private:
  /// Whether any surface is translucent (Opacity or an iso-value opacity below 1).
  bool IsTranslucent();
  /// The renderer's EndEvent: translucent surfaces composited across the rendering processes.
  void DrawTranslucent(vtkObject* caller, unsigned long event, void* data);
  /// Says why the input cannot be drawn (empty, no finite point, Contour By missing or not one
  /// component), once per change of the input or of Contour By; false then.
  void CheckInput();
  /// The actor is shown when the representation is and its input can be drawn.
  void UpdateActorVisibility();

  vtkDirectSurfaceRepresentation(const vtkDirectSurfaceRepresentation&) = delete;
  void operator=(const vtkDirectSurfaceRepresentation&) = delete;

  vtkNew<vtkDirectSurfaceMapper> Mapper;
  vtkNew<vtkActor> Actor;
  vtkNew<vtkProperty> Property;
  /// A shallow copy of the input (an empty grid when there is none), the piece handed to the view.
  vtkSmartPointer<vtkDataObject> Piece;
  double DataBounds[6];
  /// The view's renderer, observed for DrawTranslucent.
  vtkRenderer* Renderer = nullptr;
  unsigned long DrawTranslucentTag = 0;
  bool Visible = true;
  /// Contour By's array (association and name).
  int ContourByAssociation = 0;
  std::string ContourByName;
  /// The input of the last RequestData (whether there was one, its modification time), and
  /// what CheckInput last looked at (that time and Contour By) and found.
  bool HasInput = false;
  vtkMTimeType InputTime = 0;
  vtkMTimeType CheckedInputTime = 0;
  std::string CheckedContourBy;
  bool InputDrawable = true;
  /// Whether the piece the view delivered for this render has cells.
  bool DeliveredDrawable = true;
  /// Under ordered compositing the mapper composites opaque surfaces across the processes too
  /// (vtkDirectSurfaceMapper::SetCompositeOpaqueAcrossProcesses); said once each time it starts.
  void FollowOrderedCompositing();
  bool WarnedOrderedCompositing = false;
  /// Lists refused for a count of numbers that is not whole colours or planes.
  bool IsoValueColorsRefused = false;
  bool ClipPlanesRefused = false;
};

#endif
