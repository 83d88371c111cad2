#include "vtkSMDirectSurfaceRayCasterInitializationHelper.h"

#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMProxyManager.h"
#include "vtkSMSessionProxyManager.h"
#include "vtkWeakPointer.h"

#include <cstring>

vtkStandardNewMacro(vtkSMDirectSurfaceRayCasterInitializationHelper);

namespace
{
/// On the proxy manager's RegisterEvent: a new representation of the filter's output gets Map
/// Scalars off. Removes itself once the filter proxy is deleted.
class MapScalarsOff : public vtkCommand
{
public:
  static MapScalarsOff* New() { return new MapScalarsOff; }
  vtkWeakPointer<vtkSMProxy> Producer;

  void Execute(vtkObject* caller, unsigned long, void* callData) override
  {
    if (!this->Producer)
    {
      caller->RemoveObserver(this);
      return;
    }
    const auto* info = static_cast<vtkSMProxyManager::RegisteredProxyInformation*>(callData);
    if (!info || info->Type != vtkSMProxyManager::RegisteredProxyInformation::PROXY ||
      !info->GroupName || std::strcmp(info->GroupName, "representations") != 0)
    {
      return;
    }
    vtkSMProxy* representation = info->Proxy;
    if (representation->GetProperty("Input") && representation->GetProperty("MapScalars") &&
      vtkSMPropertyHelper(representation, "Input").GetAsProxy() == this->Producer)
    {
      vtkSMPropertyHelper(representation, "MapScalars").Set(0);
      representation->UpdateVTKObjects();
    }
  }
};
}

void vtkSMDirectSurfaceRayCasterInitializationHelper::PostInitializeProxy(
  vtkSMProxy*, vtkPVXMLElement*, vtkMTimeType)
{
}

void vtkSMDirectSurfaceRayCasterInitializationHelper::RegisterProxy(
  vtkSMProxy* proxy, vtkPVXMLElement*)
{
  vtkSMSessionProxyManager* manager = proxy ? proxy->GetSessionProxyManager() : nullptr;
  if (!manager)
  {
    return;
  }
  vtkNew<MapScalarsOff> observer;
  observer->Producer = proxy;
  manager->AddObserver(vtkCommand::RegisterEvent, observer);
}

void vtkSMDirectSurfaceRayCasterInitializationHelper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
