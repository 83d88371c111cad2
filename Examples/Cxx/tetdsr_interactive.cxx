// Views the exact isosurface of a quadratic tetrahedral mesh in an interactive render window
// (vtkDirectSurfaceMapper), or renders one frame offscreen to a PNG.
//   tetdsr-interactive <mesh.vtu> <point array> <iso-value> [--screenshot out.png] [--size W H]
// Left drag rotates, right drag / wheel zooms, middle drag pans (VTK's trackball camera); while
// the camera moves the surface is cast at a reduced resolution, full resolution when it stops.
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkDirectSurfaceMapper.h"
#include "vtkInteractorStyleTrackballCamera.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
// Turns pipeline and rendering errors into a non-zero exit status.
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

int Usage(const char* program)
{
  std::cerr << "usage: " << program
            << " <mesh.vtu> <point array> <iso-value> [--screenshot out.png] [--size W H]\n";
  return EXIT_FAILURE;
}
}

int main(int argc, char* argv[])
{
  if (argc < 4)
  {
    return Usage(argv[0]);
  }
  std::string screenshot;
  int width = 800, height = 600;
  for (int a = 4; a < argc; ++a)
  {
    const std::string option = argv[a];
    if (option == "--screenshot" && a + 1 < argc)
    {
      screenshot = argv[++a];
    }
    else if (option == "--size" && a + 2 < argc)
    {
      width = std::atoi(argv[++a]);
      height = std::atoi(argv[++a]);
    }
    else
    {
      return Usage(argv[0]);
    }
  }
  if (width <= 0 || height <= 0)
  {
    return Usage(argv[0]);
  }

  vtkNew<ErrorObserver> errors;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(argv[1]);
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->Update();
  if (errors->Failed)
  {
    return EXIT_FAILURE;
  }
  if (!reader->GetOutput()->GetPointData()->GetArray(argv[2]))
  {
    std::cerr << argv[1] << ": no point array '" << argv[2] << "'\n";
    return EXIT_FAILURE;
  }

  vtkNew<vtkDirectSurfaceMapper> mapper;
  mapper->SetInputConnection(reader->GetOutputPort());
  mapper->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, argv[2]);
  mapper->SetValue(0, std::atof(argv[3]));
  mapper->ScalarVisibilityOff();
  mapper->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.75, 0.55);
  actor->GetProperty()->SetSpecular(0.3);
  actor->GetProperty()->SetSpecularPower(30.0);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(0.32, 0.34, 0.43);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(30.0);
  renderer->GetActiveCamera()->Elevation(25.0);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->ResetCamera();

  vtkNew<vtkRenderWindow> window;
  window->SetSize(width, height);
  window->AddRenderer(renderer);
  window->SetWindowName("tetdsr-interactive");

  if (!screenshot.empty())
  {
    window->SetOffScreenRendering(1);
    window->Render();
    if (errors->Failed)
    {
      return EXIT_FAILURE;
    }
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(screenshot.c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    std::cout << "wrote " << screenshot << " (" << mapper->GetNumberOfRenderedCells()
              << " cells)\n";
    return EXIT_SUCCESS;
  }

  vtkNew<vtkRenderWindowInteractor> interactor;
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor->SetInteractorStyle(style);
  interactor->SetRenderWindow(window);
  window->Render();
  interactor->Start();
  return errors->Failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
