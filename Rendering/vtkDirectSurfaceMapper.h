/**
 * @class   vtkDirectSurfaceMapper
 * @brief   Renders the exact isosurfaces of a higher-order finite-element field into a render window.
 *
 * A vtkMapper for a vtkUnstructuredGrid of tetrahedra (VTK_TETRA, VTK_QUADRATIC_TETRA,
 * VTK_LAGRANGE_TETRAHEDRON / VTK_BEZIER_TETRAHEDRON of orders 1 to 4), hexahedra (VTK_HEXAHEDRON,
 * VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
 * VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON / VTK_BEZIER_HEXAHEDRON of orders 1 to 4),
 * wedges (VTK_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE,
 * VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE / VTK_BEZIER_WEDGE of orders 1 to 4) and
 * pyramids (VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID), or a
 * composite dataset of them. On each render it takes the renderer's active camera and the
 * viewport's tiled size and origin, builds one ray per pixel from the inverse of the camera's
 * composite projection (so explicit and tiled projections work), ray casts the exact isosurface
 * of the polynomial field (the same core and adapter as vtkDirectSurfaceRayCaster), and draws
 * colour and window depth (0.5 z_ndc + 0.5 of each exact hit, through gl_FragDepth) with a
 * full-screen quad in the opaque pass: it composites by depth with every other prop.
 *
 * Used like any mapper:
 * @code
 * mapper->SetInputData(grid);
 * mapper->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "f");
 * mapper->SetValue(0, 0.5);
 * actor->SetMapper(mapper);
 * @endcode
 * Colour follows the standard mapper API (ScalarVisibility, SetScalarModeToUsePointFieldData +
 * SelectColorArray, SetLookupTable, SetScalarRange / UseLookupTableScalarRange, ColorMode); the
 * actor's vtkProperty gives colour, opacity, ambient / diffuse / specular; the renderer's lights
 * light it as vtkOpenGLPolyDataMapper lights polygons (no light, a lone headlight, or Phong per
 * light); the mapper's clipping planes (at most 6) cut it.
 *
 * Level of detail: while the render window's desired update rate is above its interactor's
 * still update rate and at least one frame a second (the camera is being moved; ParaView's still
 * renders ask 0.002), the image is cast at a reduced resolution
 * (ImageSampleDistance) chosen so that the frame meets the actor's allocated render time (the
 * time the rest of the last frame took, between two renders, is not the cast's to spend), and
 * upscaled edge- and depth-aware (a joint bilateral filter over the cast's 2 x 2 pixels around
 * each window pixel: colour never crosses a silhouette or a depth discontinuity, and coverage is
 * the nearest cast pixel's). A still render is at full resolution; after interaction with a
 * running interactor it is cast in the background (ProgressiveRefinement). A render with
 * unchanged camera, viewport, data and settings re-uses the last image. Abort requests are
 * honoured (CheckAbortStatus).
 *
 * @warning The prepared scene (validation) is built once per mesh and field and kept, with the
 * acceleration structure of the last iso-values. Iso-value opacities below 1 (or the actor's opacity) composite this mapper's own
 * surfaces front to back, up to the opaque geometry's depth, and the result is blended over the
 * finished frame: correct with opaque props, with plain blending, order-independent
 * translucency and depth peeling alike; other translucent props are seen behind it, never in
 * front. Several actors sharing one translucent mapper are each drawn, blended farthest first
 * (by the distance of their centres from the camera), not sorted per pixel. One mapper may serve
 * several actors, renderers and windows: each view keeps its own last image. An input with
 * empty bounds (no cells, only non-finite points, an empty composite dataset), which VTK's
 * culler drops before Render, is reported when its bounds are asked for. Positional lights are point lights without attenuation or cone.
 *
 * Hardware selection (vtkHardwareSelector: ParaView's Select Cells / Points On, hovering,
 * vtkPropPicker, vtkRenderer::PickProp) sees the surface: in each of the selector's passes the
 * mapper draws, at every pixel the surface covers and at its exact depth, the id asked for: the
 * actor's, the process's, the block's flat index (1 for a dataset), the input cell the ray hits,
 * or that cell's node nearest the hit. Translucent surfaces are selected at their nearest
 * crossing. For the exact hit itself (point, normal, values), see Pick and vtkDirectSurfacePicker.
 *
 * @sa vtkDirectSurfaceRayCaster
 */
#ifndef vtkDirectSurfaceMapper_h
#define vtkDirectSurfaceMapper_h

#include "TetDSRRenderingModule.h" // for export macro
#include "vtkMapper.h"
#include "vtkNew.h" // for vtkNew

#include <memory> // for std::unique_ptr

class vtkDirectSurfacePick;
class vtkMultiProcessController;

class vtkContourValues;
class vtkRenderWindowInteractor;
class vtkTimerLog;
class vtkUnstructuredGrid;

class TETDSRRENDERING_EXPORT vtkDirectSurfaceMapper : public vtkMapper
{
public:
  static vtkDirectSurfaceMapper* New();
  vtkTypeMacro(vtkDirectSurfaceMapper, vtkMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The mesh: a vtkUnstructuredGrid, or a composite dataset of them (or use SetInputConnection).
   * Other data objects are refused with an error (the input is kept).
   */
  void SetInputData(vtkDataObject* input);

  /**
   * The colour map's range (vtkMapper's): a NaN or infinite end is refused with an error.
   */
  void SetScalarRange(double lo, double hi) override;
  using vtkMapper::SetScalarRange;

  ///@{
  /**
   * Iso-values, as on vtkContourFilter (default: one, 0).
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
   * Colour and opacity of the i-th iso-value's surface. Unset colours take the actor's colour
   * (when not colour-mapped); unset opacities are 1; each is multiplied by the actor's opacity.
   * Indices outside [0, 2^20) are refused with an error.
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
   * Translucent surfaces of an input distributed over several processes (each holding some of
   * the cells; ParaView's rendering processes under MPI): with a controller of several
   * processes, Render draws opaque surfaces only, and every process calls
   * DrawTranslucentAcrossProcesses once per frame, after the processes' opaque images are
   * composited (vtkDirectSurfaceRepresentation does, at its renderer's EndEvent). Each process
   * casts the crossings of the cells it holds; process 0 sorts them all along each ray, keeps
   * those in front of the composited depth, composites them front to back exactly as one process
   * holding every cell would, and blends them over its frame: the serial picture whatever the
   * distribution of the cells. `compositedDepth` is that depth (window coordinates, `frameSize`
   * pixels covering the viewport, row-major from the bottom); null (no compositor, or one that
   * blends without depth) composites every process's own depth buffer, the nearest of each
   * pixel. `compositedColors`, when given (RGBA, premultiplied, as a compositor such as IceT
   * holds its image, `frameSize` pixels), is blended into in place, before it is shown;
   * otherwise the surfaces are drawn over process 0's frame buffer. With FXAA on, the renderer
   * applies it after these surfaces (PostponeFXAA). Collective: a process with
   * no input, an invisible or opaque actor, or no window takes part with no crossings. The
   * default controller is none.
   */
  void SetController(vtkMultiProcessController* controller);
  vtkMultiProcessController* GetController();
  void DrawTranslucentAcrossProcesses(vtkRenderer* renderer, vtkActor* actor,
    const float* compositedDepth, unsigned char* compositedColors, const int frameSize[2]);
  ///@}

  ///@{
  /**
   * With a controller of several processes, opaque surfaces too are left to
   * DrawTranslucentAcrossProcesses (composited there by depth across the processes, exactly, and
   * drawn over the compositor's image): for compositors that blend the processes' images in an
   * order without depth, such as ParaView's ordered compositing, which would otherwise show one
   * process's surfaces over another's whatever their depth. Other props' translucent geometry in
   * front of these surfaces is then hidden by them (it was blended into the compositor's image
   * before them). Default off.
   */
  vtkSetMacro(CompositeOpaqueAcrossProcesses, bool);
  vtkGetMacro(CompositeOpaqueAcrossProcesses, bool);
  vtkBooleanMacro(CompositeOpaqueAcrossProcesses, bool);
  ///@}

  ///@{
  /**
   * Picking the exact surface. Pick: what `actor` shows through `renderer`'s camera at a display
   * position in a still frame, in display coordinates as VTK's pickers take them (pixels from
   * the render window's lower left, continuous: pixel (i, j) covers [i, i + 1) x [j, j + 1), and
   * (i + 0.5, j + 0.5) gives exactly the hit that pixel shows). PickSegment: the first hit from p1 towards
   * p2 (the input's coordinates), what vtkDirectSurfacePicker asks. Both fill `result` (world
   * and input position, cell, parametric coordinates, the field and every point array
   * interpolated there, the exact normal: vtkDirectSurfacePick) with the iso-values, clipping
   * planes and caps of the next render, and return whether anything was hit.
   */
  bool Pick(double x, double y, vtkRenderer* renderer, vtkActor* actor, vtkDirectSurfacePick* result);
  bool PickSegment(const double p1[3], const double p2[3], vtkActor* actor, vtkDirectSurfacePick* result);
  ///@}

  ///@{
  /**
   * Level of detail while interacting. With AutoAdjustSampleDistances (default on) each
   * interactive frame casts one ray per ImageSampleDistance x ImageSampleDistance pixels, the
   * distance adjusted from the last frame's time to meet the actor's allocated render time,
   * within [1, MaximumImageSampleDistance] (default 8). Off: InteractiveImageSampleDistance
   * (default 2) while interacting. Still renders always use 1. Both distances are clamped to
   * [1, 64]; NaN is refused with an error (the value is kept).
   */
  vtkSetMacro(AutoAdjustSampleDistances, bool);
  vtkGetMacro(AutoAdjustSampleDistances, bool);
  vtkBooleanMacro(AutoAdjustSampleDistances, bool);
  virtual void SetMaximumImageSampleDistance(double distance);
  vtkGetMacro(MaximumImageSampleDistance, double);
  virtual void SetInteractiveImageSampleDistance(double distance);
  vtkGetMacro(InteractiveImageSampleDistance, double);
  ///@}

  ///@{
  /**
   * Progressive refinement (default on): in a window whose interactor runs an event loop, a
   * still render whose full-resolution cast would take more than a fraction of a second (0.15 s,
   * judged from the last cast's time per ray; any first render) does not keep the loop's thread
   * busy: it shows an image at once, the last reduced image of the same view after
   * interaction, else a coarse cast of its own sized to take about 0.05 s (after a change of
   * iso-value, colours, camera, input or window size, and on the first render), and casts the
   * full resolution on worker threads (NumberOfThreads); when it is done, a timer on the
   * interactor asks for a render, which shows it. A new interactive frame, a changed camera,
   * input or setting, or a cast for another view of this mapper cancels the background cast (it
   * stops within one image tile). The event loop is known to run once a one-shot timer the
   * mapper sets on the interactor, when it first draws in its window, has fired (Start, or
   * ProcessEvents); every mapper of the process then knows it from its first render. Without one
   * (batch and offscreen scripts, scripts that only call Render, even with an interactor
   * attached), with SynchronousStillRenders, or off, a still render casts at full resolution
   * before it returns.
   * @warning A script that has processed the interactor's events (so the mapper knows the
   * loop) and reads the window back right after a still render gets the image shown at once:
   * switch SynchronousStillRenders on around the capture, or process the interactor's events
   * until the last render is no longer refining (GetLastRenderRefining).
   */
  vtkSetMacro(ProgressiveRefinement, bool);
  vtkGetMacro(ProgressiveRefinement, bool);
  vtkBooleanMacro(ProgressiveRefinement, bool);
  ///@}

  ///@{
  /**
   * While on (default off), every still render is cast at full resolution before it returns,
   * even in a window whose event loop runs: for captures of the window (ParaView's
   * representation turns it on while its view takes a screenshot). The images are the same
   * either way, so setting it does not modify the mapper (its last image is re-used).
   */
  void SetSynchronousStillRenders(bool synchronous) { this->SynchronousStillRenders = synchronous; }
  bool GetSynchronousStillRenders() const { return this->SynchronousStillRenders; }
  ///@}

  ///@{
  /**
   * What the last render did: the sample distance of the image it drew (1: full resolution),
   * whether it re-used the previous image, the image's size in rays, and whether it drew the
   * last reduced image while the full resolution is cast in the background
   * (ProgressiveRefinement).
   */
  vtkGetMacro(LastImageSampleDistance, double);
  vtkGetMacro(LastRenderReusedImage, bool);
  vtkGetVector2Macro(LastCastSize, int);
  vtkGetMacro(LastRenderRefining, bool);
  ///@}

  ///@{
  /**
   * Threads for preprocessing and casting (0, the default: all cores).
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  /**
   * Cells of the last render's input that are rendered (the rest were skipped with warnings).
   */
  vtkGetMacro(NumberOfRenderedCells, vtkIdType);

  void Render(vtkRenderer* renderer, vtkActor* actor) override;

  /**
   * Tells the mapper that `interactor`'s event loop runs (ProgressiveRefinement needs one), for
   * an application that embeds its windows in its own event loop and knows it before the first
   * render (ParaView's GUI: the representation says so when it is added to a view), so that the
   * first render is shown at once too. Otherwise the mapper finds out from a timer it sets at its
   * first render.
   */
  void DeclareEventLoopRuns(vtkRenderWindowInteractor* interactor);

  ///@{
  /**
   * Translucent surfaces (an iso-value opacity, or the actor's, below 1) are drawn once per
   * frame after the renderer's passes (on its EndEvent): cast up to the opaque geometry's depth
   * read from the frame buffer, composited front to back, and blended over the finished frame.
   * Opaque ones are drawn in the opaque pass with their depth.
   */
  bool HasOpaqueGeometry() override;
  bool HasTranslucentPolygonalGeometry() override;
  ///@}
  void ReleaseGraphicsResources(vtkWindow* window) override;

  ///@{
  /**
   * The input's bounds (a composite input: the union of its blocks'), so that ResetCamera and
   * the clipping ranges see the mesh.
   */
  double* GetBounds() override;
  void GetBounds(double bounds[6]) override { this->Superclass::GetBounds(bounds); }
  ///@}

  vtkMTimeType GetMTime() override;

protected:
  vtkDirectSurfaceMapper();
  ~vtkDirectSurfaceMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  vtkNew<vtkContourValues> ContourValues;
  bool AutoAdjustSampleDistances = true;
  double MaximumImageSampleDistance = 8.0;
  double InteractiveImageSampleDistance = 2.0;
  bool ProgressiveRefinement = true;
  bool CompositeOpaqueAcrossProcesses = false;
  bool SynchronousStillRenders = false;
  int NumberOfThreads = 0;

  double LastImageSampleDistance = 1.0;
  bool LastRenderReusedImage = false;
  bool LastRenderRefining = false;
  int LastCastSize[2] = { 0, 0 };
  vtkIdType NumberOfRenderedCells = 0;

private:
  vtkDirectSurfaceMapper(const vtkDirectSurfaceMapper&) = delete;
  void operator=(const vtkDirectSurfaceMapper&) = delete;

  struct Frame;
  struct ImageCast;
  struct Refinement;
  /// Casts and draws: opaque surfaces with depth, or translucent ones blended over the frame.
  void Draw(vtkRenderer* renderer, vtkActor* actor, bool translucent);
  /// A pass of the renderer's hardware selector: the ids it asks for (the actor's, the
  /// process's, the block's flat index, the input's cell, the cell's node nearest the hit) of
  /// each pixel a surface covers, at its exact depth.
  void DrawSelection(vtkRenderer* renderer, vtkActor* actor);
  /// Records a finished cast (its time sizes the next interactive frame's sample distance).
  void CastFinished(const Frame& frame, double sampleDistance, double seconds);
  /// Pick and PickSegment: the ray (origin, unit direction, the input's coordinates) up to
  /// tLimit, with `frame`'s actor matrices set; `scale` turns the ray's parameter into the
  /// result's.
  bool PickRay(Frame& frame, const double origin[3], const double direction[3], double tLimit,
    double scale, vtkDirectSurfacePick* result);
  /// The input's unstructured grids, by flat index; forgets the prepared meshes of blocks it no
  /// longer has. False, with an error, when it has none.
  bool CollectBlocks(Frame& frame);
  /// Level of detail: 1 for a still render, else a reduced resolution (pixels a ray along each
  /// axis) sized to the actor's allocated render time.
  double ChooseSampleDistance(const Frame& frame);
  /// What the image depends on, into frame.Signature: what decides which cell each pixel shows
  /// (matrices, modification times: a selection's passes share a cast by it), and with `shading`
  /// also what decides its colour (lights, the opaque depth under translucent surfaces). An
  /// unchanged signature (and cast size) re-uses the last image.
  void ComputeSignature(Frame& frame, bool shading);
  /// The iso-values, the clipping planes in model coordinates and the actor's material; false,
  /// with the errors, when they cannot be cast.
  bool ConvertSettings(Frame& frame);
  /// Makes `cast` ready for the frame: its images sized, a caster for each block that can be
  /// rendered (its prepared mesh current, its colours chosen), what was skipped reported. False
  /// when no cell is rendered.
  bool PrepareCast(Frame& frame, ImageCast& cast);
  /// Casts every block into one image on this thread; false when there is nothing to draw
  /// (aborted, or no cell rendered).
  bool CastBlocks(Frame& frame);
  /// Makes a block's prepared mesh current (its field checked, its scene built or re-used);
  /// false, with the messages in the frame, when nothing of it can be rendered.
  bool PrepareBlock(Frame& frame, unsigned int index, vtkUnstructuredGrid* grid);
  /// ProgressiveRefinement for a still frame (the frame set up at full resolution): shown at once
  /// (the last reduced image of the same scene, or a coarse cast of its own) while the full
  /// resolution is cast on worker threads. False when the full cast is quick (then the caller
  /// casts it); true when the frame is done (drawn, or nothing to draw).
  bool DrawThenRefine(Frame& frame, vtkRenderer* renderer, vtkRenderWindowInteractor* interactor,
    vtkTimerLog* timer);
  /// The sample distance of a still frame's coarse cast: about kCoarseFrameSeconds from the last
  /// cast's time per ray (the maximum before any cast); 1 when the full cast is quick.
  double ChooseCoarseSampleDistance(const Frame& frame);
  /// Whether `interactor`'s event loop runs (its timers fire); the first call sets the timer
  /// that tells, and observes the interactor's timers.
  bool EventLoopRuns(vtkRenderWindowInteractor* interactor);
  /// The full-resolution cast's time expected from the last cast's time per ray; -1 before any.
  double ExpectedFullCastSeconds(const Frame& frame) const;
  /// ProgressiveRefinement: the frame cast on worker threads, with a timer on `interactor` that
  /// asks for a render when it is done; null when there is nothing to cast.
  std::unique_ptr<Refinement> StartRefinement(Frame& frame, vtkRenderWindowInteractor* interactor);
  /// A still frame of a view whose background cast runs: true when that cast is of this scene
  /// (then the view's image is to be drawn): a finished cast is uploaded, a running one waited for
  /// by a capture (SynchronousStillRenders).
  bool ShowRefinement(Frame& frame, vtkRenderer* renderer);
  /// An interactor's TimerEvent: its event loop runs, or a view's background cast is done (then
  /// it asks the interactor for a render).
  void TimerFired(vtkObject* interactor, unsigned long event, void* timerId);
  /// The renderer's EndEvent: draws the translucent surfaces its actors of this mapper asked
  /// for, farthest actor first.
  void DrawDeferred(vtkObject* renderer, unsigned long event, void* data);
  /// Warns (once per change) when the renderer has other translucent props, which translucent
  /// surfaces, blended over the finished frame, cannot interleave with.
  void CheckTranslucentNeighbours(vtkRenderer* renderer);
  /// Translucent surfaces are drawn after the renderer's passes, which end with its FXAA (VTK
  /// applies it after the translucent polygons; ParaView's compositors after compositing): so
  /// that they are anti-aliased as every other surface, this switches the renderer's FXAA off
  /// for the frame, and ApplyPostponedFXAA (its EndEvent, after every translucent draw at
  /// priority 1) applies it over the finished frame and switches it back on. Nothing to do
  /// where FXAA is off (ParaView's compositors switch it off while the processes render).
  void PostponeFXAA(vtkRenderer* renderer);
  void ApplyPostponedFXAA(vtkObject* renderer, unsigned long event, void* data);
  /// The culler drops an actor whose bounds are empty before Render is called: then (once per
  /// change of the input or the settings) the reason is reported from GetBounds.
  void ReportWhyNothingIsDrawn();
  bool IsTranslucent(vtkActor* actor);

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
