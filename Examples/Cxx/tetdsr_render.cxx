// Renders the isosurface of a quadratic tetrahedral mesh to a PNG from C++.
//   tetdsr-render <mesh.vtu> <iso-value> <out.png> [width height]
#include "vtkCommand.h"
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <cstdlib>
#include <iostream>

namespace
{
// Turns pipeline errors into a non-zero exit status. Watch the reader too: when it fails, the
// pipeline stops before the caster runs.
class ErrorObserver : public vtkCommand
{
public:
  static ErrorObserver* New() { return new ErrorObserver; }
  void Execute(vtkObject*, unsigned long, void* message) override
  {
    std::cerr << static_cast<const char*>(message) << "\n";
    this->Failed = true;
  }
  bool Failed = false;
};
}

int main(int argc, char* argv[])
{
  if (argc != 4 && argc != 6)
  {
    std::cerr << "usage: " << argv[0] << " <mesh.vtu> <iso-value> <out.png> [width height]\n";
    return EXIT_FAILURE;
  }
  vtkNew<ErrorObserver> errors;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(argv[1]);
  reader->AddObserver(vtkCommand::ErrorEvent, errors);

  vtkNew<vtkDirectSurfaceRayCaster> caster;
  caster->SetInputConnection(reader->GetOutputPort());
  caster->SetValue(0, std::atof(argv[2]));
  if (argc == 6)
  {
    caster->SetImageSize(std::atoi(argv[4]), std::atoi(argv[5]));
  }
  caster->AddObserver(vtkCommand::ErrorEvent, errors);
  caster->Update();
  if (errors->Failed)
  {
    return EXIT_FAILURE;
  }

  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(argv[3]);
  writer->SetInputConnection(caster->GetOutputPort());
  writer->Write();
  std::cout << "wrote " << argv[3] << " (" << caster->GetNumberOfRenderedCells() << " cells)\n";
  return EXIT_SUCCESS;
}
