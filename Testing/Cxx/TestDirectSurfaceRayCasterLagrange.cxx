// A torus (a polynomial of degree 4) on 48 straight VTK_LAGRANGE_TETRAHEDRON cells of order 4,
// their nodes at vtkLagrangeTetra's own parametric coordinates: every hit must lie on the
// analytic surface (residual |f| / |grad f| below 1e-9 of the diagonal) with the analytic normal,
// and the image must match the baseline. (Testing/Python/test_higher_order.py compares every
// pixel with the first root along its ray.)
#include "LatticeMesh.h" // forEachKuhnTet
#include "TetDSRTestSupport.h"

#include "vtkCellArray.h"
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkDoubleArray.h"
#include "vtkLagrangeTetra.h"

#include <array>
#include <cstdlib>
#include <iostream>
#include <map>

namespace
{
const double kCentre[3] = { 0.5, 0.47, 0.52 };
const double kMajor = 0.28, kMinor = 0.11;

double Torus(const double x[3], double gradient[3])
{
  const double d[3] = { x[0] - kCentre[0], x[1] - kCentre[1], x[2] - kCentre[2] };
  const double s = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + kMajor * kMajor - kMinor * kMinor;
  for (int a = 0; a < 3; ++a)
  {
    gradient[a] = 4.0 * s * d[a] - (a < 2 ? 8.0 * kMajor * kMajor * d[a] : 0.0);
  }
  return s * s - 4.0 * kMajor * kMajor * (d[0] * d[0] + d[1] * d[1]);
}

/// [0, 1]^3 as n^3 cubes of 6 Kuhn tets, each an order-4 Lagrange tet with straight sides.
vtkSmartPointer<vtkUnstructuredGrid> TorusGrid(int n)
{
  constexpr int kOrder = 4;
  vtkNew<vtkLagrangeTetra> reference;
  reference->GetPointIds()->SetNumberOfIds(35);
  reference->GetPoints()->SetNumberOfPoints(35);
  for (int k = 0; k < 35; ++k)
  {
    reference->GetPointIds()->SetId(k, k);
  }
  reference->Initialize();
  const double* pcoords = reference->GetParametricCoords();

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> values;
  values->SetName("torus");
  std::map<std::array<long, 3>, vtkIdType> shared;
  vtkNew<vtkCellArray> cells;
  tetdsr_test::forEachKuhnTet(n, 1, tetdsr_test::CubeOrder::ZFastest,
    [&](const std::array<tetdsr_test::LatticeKey, 4>& v) {
      vtkIdType ids[35];
      for (int node = 0; node < 35; ++node)
      {
        const double* pc = pcoords + 3 * node;
        const double L[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
        std::array<long, 3> key{};
        for (int a = 0; a < 3; ++a)
        {
          double sum = 0.0;
          for (int q = 0; q < 4; ++q)
          {
            sum += kOrder * L[q] * v[q][a];
          }
          key[a] = std::lround(sum);
        }
        auto it = shared.find(key);
        if (it == shared.end())
        {
          const double x[3] = { key[0] / double(kOrder * n), key[1] / double(kOrder * n),
            key[2] / double(kOrder * n) };
          double gradient[3];
          it = shared.emplace(key, points->InsertNextPoint(x)).first;
          values->InsertNextValue(Torus(x, gradient));
        }
        ids[node] = it->second;
      }
      cells->InsertNextCell(35, ids);
    });
  grid->SetPoints(points);
  grid->SetCells(VTK_LAGRANGE_TETRAHEDRON, cells);
  grid->GetPointData()->SetScalars(values);
  return grid;
}
} // namespace

int TestDirectSurfaceRayCasterLagrange(int argc, char* argv[])
{
  vtkSmartPointer<vtkUnstructuredGrid> grid = TorusGrid(2);
  vtkNew<vtkCamera> camera;
  camera->SetPosition(1.7, 1.35, 2.5);
  camera->SetFocalPoint(0.5, 0.5, 0.5);
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetViewAngle(22.0);

  vtkNew<vtkDirectSurfaceRayCaster> caster;
  caster->SetInputData(grid);
  caster->SetValue(0, 0.0);
  caster->SetCamera(camera);
  caster->SetImageSize(240, 200);
  caster->SetSurfaceColor(0.55, 0.75, 0.9);
  caster->Update();

  vtkImageData* image = caster->GetOutput();
  vtkDataArray* depth = image->GetPointData()->GetArray("Depth");
  vtkDataArray* normals = image->GetPointData()->GetArray("Normals");
  const double diagonal = std::sqrt(3.0);
  int covered = 0;
  double worstResidual = 0.0, worstAngle = 0.0;
  for (int j = 0; j < 200; ++j)
  {
    for (int i = 0; i < 240; ++i)
    {
      const vtkIdType pixel = i + 240 * j;
      const double t = depth->GetComponent(pixel, 0);
      if (!std::isfinite(t))
      {
        continue;
      }
      ++covered;
      const tetdsr_truth::Ray ray = tetdsr_truth::PixelRay(camera, 240, 200, i, j);
      double x[3], gradient[3], normal[3];
      for (int a = 0; a < 3; ++a)
      {
        x[a] = ray.origin[a] + t * ray.direction[a];
        normal[a] = normals->GetComponent(pixel, a);
      }
      const double f = Torus(x, gradient);
      worstResidual = std::max(worstResidual, std::abs(f) / vtkMath::Norm(gradient) / diagonal);
      worstAngle = std::max(worstAngle, vtkMath::AngleBetweenVectors(normal, gradient));
    }
  }
  std::cout << "Torus on 48 Lagrange order-4 cells: " << covered << " pixels, max residual "
            << worstResidual << " of the diagonal, max normal error " << worstAngle << " rad\n";

  tetdsr_truth::Checks check;
  check(caster->GetNumberOfHigherOrderCells() == 48, "all 48 cells should be read as order 4");
  check(caster->GetNumberOfRenderedCells() == 48, "all 48 cells should be rendered");
  check(caster->GetNumberOfCurvedCells() == 0, "the cells should be straight");
  check(covered > 8000, "the torus should cover more than 8000 pixels");
  check(worstResidual < 1e-9, "every hit should lie on the torus within 1e-9 of the diagonal");
  check(worstAngle < 1e-6, "every normal should be within 1e-6 rad of the gradient");
  check(tetdsr_truth::MatchesBaseline(argc, argv, caster), "image should match the baseline");
  return check.ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
