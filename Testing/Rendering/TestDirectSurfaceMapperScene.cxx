// vtkDirectSurfaceMapper among other props in one render window, against a baseline image: the
// exact sphere |x|^2 = 0.5 (coloured by x through a lookup table, cut by a clipping plane), an
// opaque box that cuts into it, and vtkContourFilter's surface of another iso-value (0.15) of
// the same mesh. Depth compositing decides every overlap.
#include "LatticeGrid.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkContourFilter.h"
#include "vtkCubeSource.h"
#include "vtkDirectSurfaceMapper.h"
#include "vtkLookupTable.h"
#include "vtkPlane.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

int TestDirectSurfaceMapperScene(int argc, char* argv[])
{
  tetdsr_test::LatticeMesh lattice = tetdsr_test::makeLattice(4, glm::dvec3(-1.0), 2.0);
  lattice.sample([](const glm::dvec3& x) { return glm::dot(x, x); });
  vtkSmartPointer<vtkUnstructuredGrid> mesh = tetdsr_test::ToGrid(lattice);
  vtkNew<vtkDoubleArray> xArray;
  xArray->SetName("x");
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    xArray->InsertNextValue(mesh->GetPoint(p)[0]);
  }
  mesh->GetPointData()->AddArray(xArray);

  vtkNew<vtkLookupTable> table;
  table->SetHueRange(0.66, 0.0);
  table->Build();
  vtkNew<vtkDirectSurfaceMapper> mapper;
  mapper->SetInputData(mesh);
  mapper->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "f");
  mapper->SetValue(0, 0.5);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("x");
  mapper->SetLookupTable(table);
  mapper->SetScalarRange(-0.7, 0.7);
  vtkNew<vtkPlane> cut;
  cut->SetOrigin(0.0, 0.0, 0.35);
  cut->SetNormal(0.0, 0.0, -1.0); // keeps z <= 0.35: opens the sphere towards the viewer
  mapper->AddClippingPlane(cut);
  vtkNew<vtkActor> surface;
  surface->SetMapper(mapper);
  surface->GetProperty()->SetSpecular(0.3);
  surface->GetProperty()->SetSpecularPower(20.0);

  vtkNew<vtkCubeSource> box;
  box->SetCenter(0.55, 0.45, 0.2);
  box->SetXLength(0.5);
  box->SetYLength(0.5);
  box->SetZLength(0.9);
  vtkNew<vtkPolyDataMapper> boxMapper;
  boxMapper->SetInputConnection(box->GetOutputPort());
  vtkNew<vtkActor> boxActor;
  boxActor->SetMapper(boxMapper);
  boxActor->GetProperty()->SetColor(0.85, 0.85, 0.8);

  vtkNew<vtkContourFilter> contour;
  contour->SetInputData(mesh);
  contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "f");
  contour->SetValue(0, 0.15);
  vtkNew<vtkPolyDataMapper> contourMapper;
  contourMapper->SetInputConnection(contour->GetOutputPort());
  contourMapper->ScalarVisibilityOff();
  vtkNew<vtkActor> contourActor;
  contourActor->SetMapper(contourMapper);
  contourActor->GetProperty()->SetColor(0.2, 0.8, 0.3);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(surface);
  renderer->AddActor(boxActor);
  renderer->AddActor(contourActor);
  renderer->SetBackground(0.12, 0.12, 0.15);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(320, 280);
  window->AddRenderer(renderer);
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(1.2, 1.6, 3.2);
  camera->SetFocalPoint(0.0, 0.0, 0.0);
  camera->SetViewUp(0.0, 1.0, 0.0);
  renderer->ResetCameraClippingRange();
  window->Render();
  if (mapper->GetNumberOfRenderedCells() != 384)
  {
    std::cerr << "expected 384 rendered cells, got " << mapper->GetNumberOfRenderedCells() << "\n";
    return EXIT_FAILURE;
  }
  const int result = vtkRegressionTestImage(window);
  if (result == vtkRegressionTester::DO_INTERACTOR)
  {
    interactor->Start();
  }
  return result == vtkRegressionTester::FAILED ? EXIT_FAILURE : EXIT_SUCCESS;
}
