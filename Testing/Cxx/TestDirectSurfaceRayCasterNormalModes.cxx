// The four normal schemes. On an exactly quadratic field (sphere inside one cell) central
// differences and nodal interpolation reproduce the gradient (a quadratic's central differences
// and its nodal gradients interpolated by quadratic shape functions are exact), and depth-buffer
// normals approximate it to the image's resolution. On the paper's cube (distance sampled at the
// nodes, not polynomial) the schemes differ from the exact gradient: the errors are printed.
// The baseline is a mosaic of the cube rendered with each scheme.
#include "TetDSRTestSupport.h"

#include "vtkDirectSurfaceRayCaster.h"
#include "vtkImageAppend.h"
#include "vtkImageData.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace
{
struct NormalError
{
  double mean = 0.0, max = 0.0;
  int pixels = 0;
  bool facingViewer = true;
};

/// Angle between each mode's normals and the exact ones on the pixels both hit. Depth-buffer
/// normals face the viewer, so they are compared as lines.
NormalError Compare(vtkImageData* exact, vtkImageData* other, bool asLines)
{
  NormalError error;
  vtkDataArray* a = exact->GetPointData()->GetArray("Normals");
  vtkDataArray* b = other->GetPointData()->GetArray("Normals");
  vtkDataArray* depth = exact->GetPointData()->GetArray("Depth");
  for (vtkIdType p = 0; p < a->GetNumberOfTuples(); ++p)
  {
    if (!std::isfinite(depth->GetComponent(p, 0)))
      continue;
    double u[3], v[3];
    a->GetTuple(p, u);
    b->GetTuple(p, v);
    double angle = vtkMath::AngleBetweenVectors(u, v);
    if (asLines)
      angle = std::min(angle, vtkMath::Pi() - angle);
    error.mean += angle;
    error.max = std::max(error.max, angle);
    ++error.pixels;
  }
  error.mean /= std::max(1, error.pixels);
  return error;
}

vtkSmartPointer<vtkImageData> Render(vtkAlgorithm* reader, double iso, vtkCamera* camera, int mode)
{
  vtkNew<vtkDirectSurfaceRayCaster> caster;
  caster->SetInputConnection(reader->GetOutputPort());
  caster->SetValue(0, iso);
  caster->SetCamera(camera);
  caster->SetImageSize(160, 140);
  caster->SetNormalMode(mode);
  caster->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(caster->GetOutput());
  return image;
}

const char* kNames[] = { "exact", "central differences", "nodal interpolation", "depth buffer" };
}

int TestDirectSurfaceRayCasterNormalModes(int argc, char* argv[])
{
  tetdsr_truth::Checks check;
  // Exactly quadratic: the sphere inside one cell.
  {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(TETDSR_DATA_DIR "/sphere_in_cell.vtu");
    reader->Update();
    double centre[3];
    for (int a = 0; a < 3; ++a)
      centre[a] = reader->GetOutput()->GetFieldData()->GetArray("SphereCentre")->GetComponent(a, 0);
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint(centre);
    camera->SetPosition(centre[0] + 0.6, centre[1] + 0.5, centre[2] + 1.1);
    camera->SetViewAngle(25.0);
    vtkSmartPointer<vtkImageData> exact = Render(reader, 0.0, camera, 0);
    for (int mode = 1; mode <= 3; ++mode)
    {
      const NormalError e = Compare(exact, Render(reader, 0.0, camera, mode), mode == 3);
      std::printf("sphere inside one cell, %-20s: %d pixels, mean error %.2e rad, max %.2e rad\n",
        kNames[mode], e.pixels, e.mean, e.max);
      check(e.pixels > 2000, "the sphere should cover more than 2000 pixels");
      if (mode < 3)
        check(e.max < 1e-6, "central differences and nodal interpolation are exact on quadratics");
      else
        check(e.mean < 0.03, "depth-buffer normals should be within 0.03 rad on average");
    }
  }
  // Not polynomial: the paper's cube. Mosaic baseline of the four schemes.
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(TETDSR_DATA_DIR "/cube27.vtu");
  reader->Update();
  vtkNew<vtkCamera> camera;
  camera->SetPosition(3.0, 2.2, 4.1);
  camera->SetViewAngle(24.0);
  vtkNew<vtkImageAppend> mosaic;
  vtkSmartPointer<vtkImageData> exact = Render(reader, 0.8, camera, 0);
  mosaic->AddInputData(exact);
  for (int mode = 1; mode <= 3; ++mode)
  {
    vtkSmartPointer<vtkImageData> image = Render(reader, 0.8, camera, mode);
    const NormalError e = Compare(exact, image, mode == 3);
    std::printf("cube27 |x| = 0.8,        %-20s: %d pixels, mean error %.2e rad, max %.2e rad\n",
      kNames[mode], e.pixels, e.mean, e.max);
    check(e.pixels > 5000, "the cube's surface should cover more than 5000 pixels");
    mosaic->AddInputData(image);
  }
  mosaic->SetAppendAxis(0);
  check(tetdsr_truth::MatchesBaseline(argc, argv, mosaic), "mosaic should match the baseline");
  return check.ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
