/**
 * @class   vtkPVDirectSurfaceRayCaster
 * @brief   vtkDirectSurfaceRayCaster with its camera and clipping planes given as properties
 *
 * ParaView's server-manager properties hold numbers, not a vtkCamera or vtkPlane objects. This
 * subclass owns a camera whose parameters are properties; with FitCameraToMesh on (default) it
 * is not used and the superclass's default camera (the whole mesh, as ResetCamera places it)
 * applies. Its clipping planes are one plane edited with ParaView's interactive plane widget
 * (ClipWithPlane, SetInteractiveClipPlane) and a list of further planes (AddClipPlane); the
 * progress bar shows the filter's name. Lists of numbers that are not whole planes or colours,
 * and per-iso-value colours and opacities outside [0, 1] or NaN, are refused or clamped with the
 * core's messages.
 *
 * @sa vtkDirectSurfaceRayCaster
 */
#ifndef vtkPVDirectSurfaceRayCaster_h
#define vtkPVDirectSurfaceRayCaster_h

#include "TetDSRParaViewFiltersModule.h" // For export macro
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkNew.h"          // For vtkNew
#include "vtkPlane.h"        // For vtkSmartPointer<vtkPlane>
#include "vtkSmartPointer.h" // For vtkSmartPointer

#include <vector> // For std::vector

class TETDSRPARAVIEWFILTERS_EXPORT vtkPVDirectSurfaceRayCaster : public vtkDirectSurfaceRayCaster
{
public:
  static vtkPVDirectSurfaceRayCaster* New();
  vtkTypeMacro(vtkPVDirectSurfaceRayCaster, vtkDirectSurfaceRayCaster);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * On (default): the camera fits the whole mesh and the parameters below are ignored.
   */
  void SetFitCameraToMesh(bool fit);
  vtkGetMacro(FitCameraToMesh, bool);
  ///@}

  ///@{
  /**
   * Camera parameters, with vtkCamera's meanings and defaults.
   */
  void SetCameraPosition(double x, double y, double z);
  void SetCameraFocalPoint(double x, double y, double z);
  void SetCameraViewUp(double x, double y, double z);
  void SetCameraViewAngle(double degrees);
  void SetCameraParallelProjection(bool parallel);
  void SetCameraParallelScale(double scale);
  ///@}

  ///@{
  /**
   * The interactive clipping plane (ParaView's plane widget edits it), used while ClipWithPlane
   * is on (default off). It keeps the side its normal points to.
   */
  void SetClipWithPlane(bool clip);
  void SetInteractiveClipPlane(vtkPlane* plane);
  ///@}

  ///@{
  /**
   * Further clipping planes, through (x, y, z) with normal (nx, ny, nz), for the ClipPlanes
   * property; RemoveAllClipPlanes clears this list (not the interactive plane).
   */
  void AddClipPlane(double x, double y, double z, double nx, double ny, double nz);
  void RemoveAllClipPlanes();
  ///@}

  ///@{
  /**
   * How many numbers IsoValueColors and ClipPlanes hold (vtkSIDirectSurfaceListProperty calls
   * these before the values): a count that is not whole colours (3) or planes (6) refuses the
   * list, with an error (ParaView would cut it to whole ones without a word).
   */
  void SetIsoValueColorsCount(int count);
  void SetClipPlanesCount(int count);
  ///@}

  ///@{
  /**
   * The superclass's, unless the IsoValueColors list was refused; components outside [0, 1]
   * are clamped with a warning and NaN refused with an error (the superclass clamps silently).
   */
  void SetIsoValueColor(int i, double red, double green, double blue);
  void SetIsoValueOpacity(int i, double opacity);
  ///@}

protected:
  vtkPVDirectSurfaceRayCaster();
  ~vtkPVDirectSurfaceRayCaster() override = default;

private:
  vtkPVDirectSurfaceRayCaster(const vtkPVDirectSurfaceRayCaster&) = delete;
  void operator=(const vtkPVDirectSurfaceRayCaster&) = delete;

  /// The superclass's clipping planes: the interactive plane if on, then the listed ones.
  void UpdateClippingPlanes();

  bool FitCameraToMesh = true;
  vtkNew<vtkCamera> PropertyCamera;
  bool ClipWithPlane = false;
  vtkSmartPointer<vtkPlane> InteractivePlane;
  std::vector<vtkSmartPointer<vtkPlane>> ListedPlanes;
  bool IsoValueColorsRefused = false;
  bool ClipPlanesRefused = false;
};

#endif
