/**
 * @class   vtkSMDirectSurfaceRayCasterInitializationHelper
 * @brief   Shows the Direct Surface Ray Cast filter's image in its own colours in ParaView
 *
 * The filter's output is an RGBA image (the `Colors` array). ParaView shows a new dataset's
 * active scalars through a colour map ("Colors Magnitude") until Map Scalars is turned off. Named
 * in the filter's XML hints (`<InitializationHelper>`), this helper turns Map Scalars off in each
 * representation made of the filter's output, when the representation is registered: in the GUI,
 * in pvpython and in pvbatch alike. The user may turn it on again.
 *
 * @sa vtkSMProxyInitializationHelper vtkPVDirectSurfaceRayCaster
 */
#ifndef vtkSMDirectSurfaceRayCasterInitializationHelper_h
#define vtkSMDirectSurfaceRayCasterInitializationHelper_h

#include "TetDSRParaViewFiltersModule.h" // For export macro
#include "vtkSMProxyInitializationHelper.h"

class TETDSRPARAVIEWFILTERS_EXPORT vtkSMDirectSurfaceRayCasterInitializationHelper
  : public vtkSMProxyInitializationHelper
{
public:
  static vtkSMDirectSurfaceRayCasterInitializationHelper* New();
  vtkTypeMacro(vtkSMDirectSurfaceRayCasterInitializationHelper, vtkSMProxyInitializationHelper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Nothing to initialize on the filter itself.
  void PostInitializeProxy(vtkSMProxy* proxy, vtkPVXMLElement* xml, vtkMTimeType) override;

  /**
   * Watches the proxy manager for representations of `proxy`'s output (until `proxy` is gone)
   * and turns their Map Scalars off.
   */
  void RegisterProxy(vtkSMProxy* proxy, vtkPVXMLElement* xml) override;

protected:
  vtkSMDirectSurfaceRayCasterInitializationHelper() = default;
  ~vtkSMDirectSurfaceRayCasterInitializationHelper() override = default;

private:
  vtkSMDirectSurfaceRayCasterInitializationHelper(
    const vtkSMDirectSurfaceRayCasterInitializationHelper&) = delete;
  void operator=(const vtkSMDirectSurfaceRayCasterInitializationHelper&) = delete;
};

#endif
