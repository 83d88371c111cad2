// A sphere strictly inside one cell: every nodal value lies above the iso-value, so
// vtkContourFilter returns nothing; the filter must show the exact sphere.
#include "TetDSRTestSupport.h"

#include "vtkContourFilter.h"
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkFieldData.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <cstdlib>
#include <iostream>
#include <string>

int TestDirectSurfaceRayCasterSphereInCell(int argc, char* argv[])
{
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(TETDSR_DATA_DIR "/sphere_in_cell.vtu");
  reader->Update();
  vtkUnstructuredGrid* mesh = reader->GetOutput();
  double centre[3], radius;
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = mesh->GetFieldData()->GetArray("SphereCentre")->GetComponent(a, 0);
  }
  radius = mesh->GetFieldData()->GetArray("SphereRadius")->GetComponent(0, 0);

  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(centre);
  camera->SetPosition(centre[0] + 0.9, centre[1] + 0.6, centre[2] + 1.5);
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetViewAngle(20.0);

  vtkNew<vtkDirectSurfaceRayCaster> caster;
  caster->SetInputConnection(reader->GetOutputPort());
  caster->SetValue(0, 0.0);
  caster->SetCamera(camera);
  caster->SetImageSize(240, 200);
  caster->SetSurfaceColor(0.9, 0.75, 0.5);
  caster->Update();

  vtkNew<vtkContourFilter> contour;
  contour->SetInputConnection(reader->GetOutputPort());
  contour->SetValue(0, 0.0);
  contour->Update();

  const double diagonal = mesh->GetLength();
  tetdsr_truth::QuadraticTruth truth(mesh, mesh->GetPointData()->GetArray("sphere"));
  tetdsr_truth::TriangleHits contourHits(contour->GetOutput());
  const tetdsr_truth::Comparison c =
    tetdsr_truth::Compare(caster->GetOutput(), camera, truth, 0.0, contourHits, diagonal);
  tetdsr_truth::Print(("Sphere inside one cell (radius " + std::to_string(radius) + ")").c_str(), c);

  tetdsr_truth::Checks check;
  check(contour->GetOutput()->GetNumberOfCells() == 0,
    "vtkContourFilter should produce no triangles (no cell straddles the iso-value)");
  check(c.contourPixels == 0, "vtkContourFilter's surface should cover no pixel");
  check(c.truthPixels > 2000, "the exact sphere should cover more than 2000 pixels");
  check(c.oursMisses == 0 && c.oursFalseHits == 0, "TetDSR coverage should equal the exact one");
  check(c.excluded < 0.02 * c.truthPixels, "the tangency band should stay under 2% of the pixels");
  check(c.oursMaxDepthError < 1e-9, "TetDSR depth error should be below 1e-9 of the diagonal");
  check(c.oursMaxNormalError < 1e-6, "TetDSR normals should be within 1e-6 rad of the gradient");
  check(c.wrongCellIds == 0, "every hit should report the cell the truth hits");
  check(caster->GetNumberOfRenderedCells() == 6, "all 6 cells should be rendered");
  check(tetdsr_truth::MatchesBaseline(argc, argv, caster), "image should match the baseline");
  return check.ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
