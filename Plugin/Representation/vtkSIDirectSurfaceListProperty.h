/**
 * @class   vtkSIDirectSurfaceListProperty
 * @brief   A repeated double vector property that tells its object how many numbers it holds
 *
 * ParaView's vtkSIDoubleVectorProperty pushes a repeated property (repeat_command) as whole
 * groups of number_of_elements_per_command numbers and drops a remainder silently: ClipPlanes
 * given 7 numbers would become one plane, given 5 none, and nobody would know. This one first
 * invokes its `count_command` (an XML attribute) with the number of values, so that the object
 * can check the count and say what is wrong, then pushes as ParaView does.
 *
 * Used with si_class="vtkSIDirectSurfaceListProperty" on a DoubleVectorProperty.
 */
#ifndef vtkSIDirectSurfaceListProperty_h
#define vtkSIDirectSurfaceListProperty_h

#include "TetDSRParaViewRepresentationsModule.h" // For export macro
#include "vtkSIDoubleVectorProperty.h"

#include <string> // For std::string

class TETDSRPARAVIEWREPRESENTATIONS_EXPORT vtkSIDirectSurfaceListProperty
  : public vtkSIDoubleVectorProperty
{
public:
  static vtkSIDirectSurfaceListProperty* New();
  vtkTypeMacro(vtkSIDirectSurfaceListProperty, vtkSIDoubleVectorProperty);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSIDirectSurfaceListProperty();
  ~vtkSIDirectSurfaceListProperty() override;

  bool Push(vtkSMMessage* message, int offset) override;
  bool ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element) override;

private:
  vtkSIDirectSurfaceListProperty(const vtkSIDirectSurfaceListProperty&) = delete;
  void operator=(const vtkSIDirectSurfaceListProperty&) = delete;

  std::string CountCommand;
};

#endif
