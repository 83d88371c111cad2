// The paper's second example: 6 quadratic tets, field = distance from the centre sampled at the
// 27 nodes. The filter must reproduce the quadratic interpolant's isosurface exactly; the linear
// contour of the same data is faceted and differs from it.
#include "TetDSRTestSupport.h"

#include "vtkContourFilter.h"
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <cstdlib>
#include <iostream>

int TestDirectSurfaceRayCasterCube(int argc, char* argv[])
{
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(TETDSR_DATA_DIR "/cube27.vtu");
  reader->Update();
  vtkUnstructuredGrid* mesh = reader->GetOutput();
  const double iso = 0.8;

  for (bool parallel : { false, true })
  {
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint(0.0, 0.0, 0.0);
    camera->SetPosition(3.0, 2.2, 4.1);
    camera->SetViewUp(0.0, 1.0, 0.0);
    camera->SetViewAngle(24.0);
    camera->SetParallelProjection(parallel);
    camera->SetParallelScale(0.9);

    vtkNew<vtkDirectSurfaceRayCaster> caster;
    caster->SetInputConnection(reader->GetOutputPort());
    caster->SetValue(0, iso);
    caster->SetCamera(camera);
    caster->SetImageSize(220, 180);
    caster->Update();

    vtkNew<vtkContourFilter> contour;
    contour->SetInputConnection(reader->GetOutputPort());
    contour->SetValue(0, iso);
    contour->Update();

    tetdsr_truth::QuadraticTruth truth(mesh, mesh->GetPointData()->GetArray("distance"));
    tetdsr_truth::TriangleHits contourHits(contour->GetOutput());
    const tetdsr_truth::Comparison c = tetdsr_truth::Compare(
      caster->GetOutput(), camera, truth, iso, contourHits, mesh->GetLength());
    tetdsr_truth::Print(parallel ? "Cube, parallel" : "Cube, perspective", c);

    tetdsr_truth::Checks check;
    check(c.truthPixels > 5000, "the exact surface should cover more than 5000 pixels");
    check(c.oursMisses == 0 && c.oursFalseHits == 0, "TetDSR coverage should equal the exact one");
    check(c.excluded < 0.01 * c.truthPixels, "the tangency band should stay under 1% of pixels");
    check(c.oursMaxDepthError < 1e-9, "TetDSR depth error should be below 1e-9 of the diagonal");
    check(c.oursMaxNormalError < 1e-6, "TetDSR normals should be within 1e-6 rad of the gradient");
    check(c.wrongCellIds == 0, "every hit should report the cell the truth hits");
    // The linear contour approximates the quadratic surface: its facets sit measurably off it.
    check(c.contourMaxDepthError > 1e-3, "the linear contour should deviate by > 1e-3 diagonal");
    check(c.contourMisses + c.contourFalseHits > 0, "the linear contour's silhouette differs");
    if (!parallel)
    {
      check(tetdsr_truth::MatchesBaseline(argc, argv, caster), "image should match the baseline");
    }
    if (!check.ok)
    {
      return EXIT_FAILURE;
    }
  }
  return EXIT_SUCCESS;
}
