#include "vtkSIDirectSurfaceListProperty.h"

#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSIDirectSurfaceListProperty);

vtkSIDirectSurfaceListProperty::vtkSIDirectSurfaceListProperty() = default;
vtkSIDirectSurfaceListProperty::~vtkSIDirectSurfaceListProperty() = default;

bool vtkSIDirectSurfaceListProperty::ReadXMLAttributes(
  vtkSIProxy* proxyhelper, vtkPVXMLElement* element)
{
  const char* command = element->GetAttribute("count_command");
  this->CountCommand = command ? command : "";
  return this->Superclass::ReadXMLAttributes(proxyhelper, element);
}

bool vtkSIDirectSurfaceListProperty::Push(vtkSMMessage* message, int offset)
{
  if (!this->CountCommand.empty() && !this->GetInformationOnly())
  {
    const ProxyState_Property& property = message->GetExtension(ProxyState::property, offset);
    vtkClientServerStream stream;
    stream << vtkClientServerStream::Invoke << this->GetVTKObject() << this->CountCommand.c_str()
           << property.value().float64_size() << vtkClientServerStream::End;
    if (!this->ProcessMessage(stream))
    {
      return false;
    }
  }
  return this->Superclass::Push(message, offset);
}

void vtkSIDirectSurfaceListProperty::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CountCommand: " << this->CountCommand << "\n";
}
