/**
 * @class   vtkPVDirectSurfaceRayCaster
 * @brief   vtkDirectSurfaceRayCaster with its camera given as properties, for ParaView
 *
 * ParaView's server-manager properties hold numbers, not a vtkCamera. This subclass owns a
 * camera whose parameters are properties; with FitCameraToMesh on (default) it is not used
 * and the superclass's default camera (the whole mesh, as ResetCamera places it) applies.
 *
 * @sa vtkDirectSurfaceRayCaster
 */
#ifndef vtkPVDirectSurfaceRayCaster_h
#define vtkPVDirectSurfaceRayCaster_h

#include "TetDSRParaViewFiltersModule.h" // For export macro
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkNew.h" // For vtkNew

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

  /**
   * Adds a clipping plane through (x, y, z) with normal (nx, ny, nz), for the ClipPlanes
   * property (RemoveAllClippingPlanes clears them).
   */
  void AddClipPlane(double x, double y, double z, double nx, double ny, double nz);

protected:
  vtkPVDirectSurfaceRayCaster() = default;
  ~vtkPVDirectSurfaceRayCaster() override = default;

private:
  vtkPVDirectSurfaceRayCaster(const vtkPVDirectSurfaceRayCaster&) = delete;
  void operator=(const vtkPVDirectSurfaceRayCaster&) = delete;

  bool FitCameraToMesh = true;
  vtkNew<vtkCamera> PropertyCamera;
};

#endif
