// Colour by a second array, clipping planes with caps, and nested translucent surfaces, against
// analytic truth. The scene is a lattice of quadratic tets filling the unit cube with the global
// quadric f = |x - c|^2, which the cells represent exactly, so every pixel's answer follows from
// ray/sphere roots clipped to the cube and to the planes, computed here without the filter.
// With flat shading (ambient 1, no diffuse or specular light) each pixel's colour is the colour
// map's or the surface's colour, composited, so colours are checked to the byte.
// The baseline is a mosaic of the four modes with the default Phong shading.
#include "LatticeGrid.h"
#include "TetDSRTestSupport.h"

#include "vtkColorTransferFunction.h"
#include "vtkDirectSurfaceRayCaster.h"
#include "vtkImageAppend.h"
#include "vtkPlane.h"

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace
{
using Vec = std::array<long double, 3>;

const Vec kCentre = { 0.52L, 0.48L, 0.5L };
constexpr int kWidth = 160;
constexpr int kHeight = 140;

long double Dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec At(const tetdsr_truth::Ray& ray, long double t)
{
  return { ray.origin[0] + t * ray.direction[0], ray.origin[1] + t * ray.direction[1],
    ray.origin[2] + t * ray.direction[2] };
}

long double Field(const Vec& x)
{
  const Vec d = { x[0] - kCentre[0], x[1] - kCentre[1], x[2] - kCentre[2] };
  return Dot(d, d);
}

// The second arrays: a quadratic scalar and a vector of quadratics (exact in the cells).
double Second(const Vec& x)
{
  return static_cast<double>(x[0] * x[1] - 0.5L * x[2] * x[2] + 0.3L * x[0]);
}
Vec Vector(const Vec& x)
{
  return { x[0], x[1] * x[1], x[2] - 0.5L };
}

struct Plane
{
  Vec origin, normal; // keeps normal . (x - origin) >= 0
};

/// The ray's kept interval: inside the unit cube and on the kept side of every plane. `entering`
/// is the plane the ray enters the kept region through (-1: none, or it enters through the
/// cube). False if nothing is kept. `margin` is the distance, in t, from t0 to the nearest other
/// plane or cube-face crossing: where it is tiny the pixel sees an edge of the region and is not
/// compared.
bool KeptInterval(const tetdsr_truth::Ray& ray, const std::vector<Plane>& planes,
  long double& t0, long double& t1, int& entering, long double& margin)
{
  long double planeIn = 0.0L, planeOut = 1e30L;
  entering = -1;
  margin = 1e30L;
  std::vector<long double> bounds;
  for (std::size_t k = 0; k < planes.size(); ++k)
  {
    const Vec o = { ray.origin[0], ray.origin[1], ray.origin[2] };
    const Vec offset = { o[0] - planes[k].origin[0], o[1] - planes[k].origin[1],
      o[2] - planes[k].origin[2] };
    const Vec d = { ray.direction[0], ray.direction[1], ray.direction[2] };
    const long double s = Dot(planes[k].normal, offset), slope = Dot(planes[k].normal, d);
    const long double t = -s / slope;
    bounds.push_back(t);
    if (slope > 0 && t > planeIn)
    {
      planeIn = t;
      entering = static_cast<int>(k);
    }
    else if (slope < 0)
    {
      planeOut = std::min(planeOut, t);
    }
  }
  long double boxIn = 0.0L, boxOut = 1e30L;
  for (int a = 0; a < 3; ++a)
  {
    const long double ta = (0.0L - ray.origin[a]) / ray.direction[a];
    const long double tb = (1.0L - ray.origin[a]) / ray.direction[a];
    boxIn = std::max(boxIn, std::min(ta, tb));
    boxOut = std::min(boxOut, std::max(ta, tb));
    bounds.push_back(ta);
    bounds.push_back(tb);
  }
  t0 = std::max(planeIn, boxIn);
  t1 = std::min(planeOut, boxOut);
  if (planeIn < boxIn)
  {
    entering = -1;
  }
  for (const long double b : bounds)
  {
    if (b != t0) // t0 is one of the bounds; the others must not compete with it
    {
      margin = std::min(margin, std::abs(b - t0));
    }
  }
  return t0 < t1;
}

/// Crossings of the sphere |x - c|^2 = iso within [t0, t1], ascending. `grazing` is set when a
/// root is within 1e-7 of an end or the ray is nearly tangent.
std::vector<long double> Crossings(const tetdsr_truth::Ray& ray, long double iso, long double t0,
  long double t1, bool& grazing)
{
  const Vec d = { ray.direction[0], ray.direction[1], ray.direction[2] };
  const Vec oc = { ray.origin[0] - kCentre[0], ray.origin[1] - kCentre[1],
    ray.origin[2] - kCentre[2] };
  const long double b = Dot(d, oc), disc = b * b - (Dot(oc, oc) - iso);
  std::vector<long double> roots;
  if (std::abs(disc) < 1e-7L * iso)
  {
    grazing = true;
  }
  if (disc <= 0)
  {
    return roots;
  }
  for (const long double t : { -b - std::sqrt(disc), -b + std::sqrt(disc) })
  {
    if (std::abs(t - t0) < 1e-7L || std::abs(t - t1) < 1e-7L)
    {
      grazing = true;
    }
    if (t >= t0 && t <= t1)
    {
      roots.push_back(t);
    }
  }
  return roots;
}

vtkSmartPointer<vtkUnstructuredGrid> MakeScene()
{
  tetdsr_test::LatticeMesh lattice = tetdsr_test::makeLattice(5, glm::dvec3(0.0), 1.0);
  lattice.sample([](const glm::dvec3& p) { return static_cast<double>(Field({ p.x, p.y, p.z })); });
  vtkSmartPointer<vtkUnstructuredGrid> grid = tetdsr_test::ToGrid(lattice);
  vtkNew<vtkDoubleArray> second, vector;
  second->SetName("g");
  vector->SetName("v");
  vector->SetNumberOfComponents(3);
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    second->InsertNextValue(Second({ x[0], x[1], x[2] }));
    const Vec v = Vector({ x[0], x[1], x[2] });
    vector->InsertNextTuple3(v[0], v[1], v[2]);
  }
  grid->GetPointData()->AddArray(second);
  grid->GetPointData()->AddArray(vector);
  return grid;
}

vtkSmartPointer<vtkImageData> Run(vtkDirectSurfaceRayCaster* caster)
{
  caster->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(caster->GetOutput());
  return image;
}

void FlatShading(vtkDirectSurfaceRayCaster* caster)
{
  caster->SetAmbient(1.0);
  caster->SetDiffuse(0.0);
  caster->SetSpecular(0.0);
}

int Byte(double channel)
{
  return static_cast<int>(std::clamp(channel, 0.0, 1.0) * 255.0 + 0.5);
}
}

int TestDirectSurfaceRayCasterAppearance(int argc, char* argv[])
{
  tetdsr_truth::Checks check;
  vtkSmartPointer<vtkUnstructuredGrid> grid = MakeScene();
  vtkNew<vtkCamera> camera;
  camera->SetPosition(1.9, 1.5, 2.3);
  camera->SetFocalPoint(0.5, 0.5, 0.5);
  camera->SetViewAngle(20.0);
  const long double iso = 0.35L * 0.35L;
  const double diagonal = std::sqrt(3.0);
  auto forEachPixel = [&](const std::function<void(vtkIdType, const tetdsr_truth::Ray&)>& body) {
    for (int j = 0; j < kHeight; ++j)
      for (int i = 0; i < kWidth; ++i)
        body(i + static_cast<vtkIdType>(j) * kWidth,
          tetdsr_truth::PixelRay(camera, kWidth, kHeight, i, j));
  };
  auto newCaster = [&]() {
    auto caster = vtkSmartPointer<vtkDirectSurfaceRayCaster>::New();
    caster->SetInputData(grid);
    caster->SetCamera(camera);
    caster->SetImageSize(kWidth, kHeight);
    caster->SetValue(0, static_cast<double>(iso));
    return caster;
  };
  vtkNew<vtkImageAppend> mosaic;
  mosaic->SetAppendAxis(0);

  // 1. Colour by a scalar, then by a vector's magnitude: the interpolated value is the analytic
  // one at the exact hit, its colour the grey colour map's.
  {
    const double lo = -0.2, hi = 0.9;
    for (int component : { 0, -1 })
    {
      vtkSmartPointer<vtkDirectSurfaceRayCaster> caster = newCaster();
      FlatShading(caster);
      caster->ColorByArrayOn();
      caster->SetInputArrayToProcess(
        1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, component == 0 ? "g" : "v");
      caster->SetColorArrayComponent(component);
      caster->SetColorMap(vtkDirectSurfaceRayCaster::GRAYSCALE);
      caster->SetColorRange(lo, hi);
      vtkSmartPointer<vtkImageData> image = Run(caster);
      vtkDataArray* values = image->GetPointData()->GetArray("ColorValues");
      vtkDataArray* colors = image->GetPointData()->GetArray("Colors");
      vtkDataArray* depth = image->GetPointData()->GetArray("Depth");
      int compared = 0, coverage = 0, colorErrors = 0;
      double valueError = 0.0;
      forEachPixel([&](vtkIdType pixel, const tetdsr_truth::Ray& ray) {
        long double t0, t1, margin;
        int entering;
        bool grazing = false;
        std::vector<long double> roots;
        if (KeptInterval(ray, {}, t0, t1, entering, margin))
          roots = Crossings(ray, iso, t0, t1, grazing);
        if (grazing)
          return;
        coverage += roots.empty() == std::isfinite(depth->GetComponent(pixel, 0));
        if (roots.empty())
          return;
        const Vec x = At(ray, roots[0]);
        double expected = Second(x);
        if (component < 0)
        {
          const Vec v = Vector(x);
          expected = static_cast<double>(std::sqrt(Dot(v, v)));
        }
        valueError = std::max(valueError, std::abs(values->GetComponent(pixel, 0) - expected));
        const int grey = Byte((expected - lo) / (hi - lo));
        colorErrors += std::abs(static_cast<int>(colors->GetComponent(pixel, 0)) - grey) > 1;
        ++compared;
      });
      std::printf("colour by %s: %d pixels, max value error %.2e, %d colours off by > 1/255, %d "
                  "coverage mismatches\n",
        component == 0 ? "g = xy - z^2/2 + 0.3x" : "|v|, v = (x, y^2, z - 1/2)", compared,
        valueError, colorErrors, coverage);
      check(compared > 3000, "the sphere should cover more than 3000 pixels");
      check(coverage == 0, "coverage should equal the analytic sphere's");
      check(valueError < 1e-9, "colour values should equal the analytic second field at the hit");
      check(colorErrors == 0, "colours should be the grey map's value to within 1/255");
    }
    vtkSmartPointer<vtkDirectSurfaceRayCaster> caster = newCaster();
    caster->ColorByArrayOn();
    caster->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "g");
    mosaic->AddInputData(Run(caster));
  }

  // 2. Two clipping planes across the sphere, off its centre (the kept part shows both the cut
  // and the outside of the sphere), with and without a cap of the region f < iso, coloured by
  // the field through a lookup table given by the user.
  const std::vector<Plane> planes = { { { 0.77L, 0.0L, 0.0L }, { -1.0L, 0.0L, 0.0L } },
    { { 0.0L, 0.0L, 0.8L }, { 0.0L, -0.3L, -1.0L } } };
  vtkNew<vtkColorTransferFunction> lookupTable;
  lookupTable->AddRGBPoint(10.0, 0.0, 0.0, 0.0); // its own range is stretched over ColorRange
  lookupTable->AddRGBPoint(20.0, 1.0, 1.0, 1.0);
  for (const bool cap : { false, true })
  {
    vtkSmartPointer<vtkDirectSurfaceRayCaster> caster = newCaster();
    for (const Plane& plane : planes)
    {
      vtkNew<vtkPlane> vtkplane;
      vtkplane->SetOrigin(static_cast<double>(plane.origin[0]), static_cast<double>(plane.origin[1]),
        static_cast<double>(plane.origin[2]));
      vtkplane->SetNormal(static_cast<double>(plane.normal[0]), static_cast<double>(plane.normal[1]),
        static_cast<double>(plane.normal[2]));
      caster->AddClippingPlane(vtkplane);
    }
    caster->SetLookupTable(lookupTable);
    caster->SetColorRange(0.0, static_cast<double>(iso));
    caster->SetCapping(
      cap ? vtkDirectSurfaceRayCaster::CAP_BELOW_ISO_VALUE : vtkDirectSurfaceRayCaster::NO_CAP);
    mosaic->AddInputData(Run(caster));
    FlatShading(caster);
    vtkSmartPointer<vtkImageData> image = Run(caster);
    vtkDataArray* depth = image->GetPointData()->GetArray("Depth");
    vtkDataArray* normals = image->GetPointData()->GetArray("Normals");
    vtkDataArray* values = image->GetPointData()->GetArray("ColorValues");
    vtkDataArray* colors = image->GetPointData()->GetArray("Colors");
    int compared = 0, coverage = 0, capPixels = 0, capTruth = 0, colorErrors = 0, excluded = 0,
        surfacePixels = 0;
    double depthError = 0.0, capValueError = 0.0, capNormalError = 0.0;
    forEachPixel([&](vtkIdType pixel, const tetdsr_truth::Ray& ray) {
      long double t0, t1, margin;
      int entering;
      bool grazing = false;
      bool capped = false;
      long double tTrue = -1.0L;
      if (KeptInterval(ray, planes, t0, t1, entering, margin))
      {
        const long double f = Field(At(ray, t0));
        grazing = margin < 1e-7L || (cap && entering >= 0 && std::abs(f - iso) < 1e-7L);
        capped = cap && entering >= 0 && f < iso;
        std::vector<long double> roots = Crossings(ray, iso, t0, t1, grazing);
        tTrue = capped ? t0 : roots.empty() ? -1.0L : roots[0];
      }
      if (grazing)
      {
        ++excluded;
        return;
      }
      const double ours = depth->GetComponent(pixel, 0);
      coverage += (tTrue >= 0) != std::isfinite(ours);
      capTruth += capped;
      if (tTrue < 0 || !std::isfinite(ours))
        return;
      ++compared;
      depthError = std::max(depthError, std::abs(ours - static_cast<double>(tTrue)) / diagonal);
      if (!capped)
      {
        ++surfacePixels;
        return;
      }
      ++capPixels;
      const double f = static_cast<double>(Field(At(ray, tTrue)));
      capValueError = std::max(capValueError, std::abs(values->GetComponent(pixel, 0) - f));
      double n[3], expected[3];
      normals->GetTuple(pixel, n);
      for (int a = 0; a < 3; ++a)
        expected[a] = static_cast<double>(planes[entering].normal[a]);
      capNormalError = std::max(capNormalError, vtkMath::AngleBetweenVectors(n, expected));
      const int grey = Byte(f / static_cast<double>(iso));
      colorErrors += std::abs(static_cast<int>(colors->GetComponent(pixel, 0)) - grey) > 1;
    });
    std::printf("clipped by 2 planes%s: %d pixels (%d excluded at region corners or tangencies), "
                "%d coverage mismatches, max depth error %.2e of the diagonal; surface %d pixels, cap %d "
                "pixels (truth %d), value error %.2e, normal error %.2e rad, %d colours off by > "
                "1/255\n",
      cap ? ", capped" : "", compared, excluded, coverage, depthError, surfacePixels, capPixels, capTruth,
      capValueError, capNormalError, colorErrors);
    check(compared > 3000, "the clipped sphere should cover more than 3000 pixels");
    check(coverage == 0, "coverage should equal the clipped analytic sphere's");
    check(depthError < 1e-9, "depth should be within 1e-9 of the diagonal");
    if (cap)
    {
      check(capPixels > 1000 && capPixels == capTruth, "the cap should cover the analytic disc");
      check(surfacePixels > 500, "the sphere's outside should show around the cap");
      check(capValueError < 1e-9, "cap colour values should equal the field on the plane");
      check(capNormalError < 1e-12, "cap normals should be the plane's");
      check(colorErrors == 0, "cap colours should be the lookup table's to within 1/255");
    }
  }

  // 3. Nested translucent spheres, values given in descending order: per-value colours and
  // opacities follow SetValue's numbering; every crossing is composited front to back.
  {
    const long double inner = 0.25L * 0.25L, outer = 0.4L * 0.4L;
    const double opacity[2] = { 0.3, 0.6 }; // outer, inner
    const double rgb[2][3] = { { 0.2, 0.4, 1.0 }, { 1.0, 0.3, 0.1 } };
    vtkSmartPointer<vtkDirectSurfaceRayCaster> caster = newCaster();
    caster->SetValue(0, static_cast<double>(outer));
    caster->SetValue(1, static_cast<double>(inner));
    for (int k = 0; k < 2; ++k)
    {
      caster->SetIsoValueColor(k, rgb[k][0], rgb[k][1], rgb[k][2]);
      caster->SetIsoValueOpacity(k, opacity[k]);
    }
    mosaic->AddInputData(Run(caster));
    FlatShading(caster);
    vtkSmartPointer<vtkImageData> image = Run(caster);
    vtkDataArray* colors = image->GetPointData()->GetArray("Colors");
    int compared = 0, wrong = 0, layers[5] = { 0, 0, 0, 0, 0 };
    forEachPixel([&](vtkIdType pixel, const tetdsr_truth::Ray& ray) {
      long double t0, t1, margin;
      int entering;
      bool grazing = false;
      std::vector<std::pair<long double, int>> crossings;
      if (KeptInterval(ray, {}, t0, t1, entering, margin))
      {
        for (int k = 0; k < 2; ++k)
          for (long double t : Crossings(ray, k == 0 ? outer : inner, t0, t1, grazing))
            crossings.emplace_back(t, k);
      }
      if (grazing)
        return;
      std::sort(crossings.begin(), crossings.end());
      double color[3] = { 0.0, 0.0, 0.0 }, alpha = 0.0;
      for (const auto& crossing : crossings)
      {
        const double weight = (1.0 - alpha) * opacity[crossing.second];
        for (int c = 0; c < 3; ++c)
          color[c] += weight * rgb[crossing.second][c];
        alpha += weight;
      }
      ++layers[crossings.size()];
      int expected[4] = { 0, 0, 0, Byte(alpha) };
      for (int c = 0; c < 3 && alpha > 0.0; ++c)
        expected[c] = Byte(color[c] / alpha);
      bool same = true;
      for (int c = 0; c < 4; ++c)
        same = same && std::abs(static_cast<int>(colors->GetComponent(pixel, c)) - expected[c]) <= 1;
      wrong += !same;
      ++compared;
    });
    std::printf("nested translucent spheres: %d pixels (0/1/2/3/4 crossings: %d/%d/%d/%d/%d), %d "
                "with an RGBA byte off by more than 1\n",
      compared, layers[0], layers[1], layers[2], layers[3], layers[4], wrong);
    check(layers[4] > 1000 && layers[2] > 1000, "rays through both spheres and through one expected");
    check(wrong == 0, "composited colours should match the analytic crossings");
  }

  check(tetdsr_truth::MatchesBaseline(argc, argv, mosaic), "mosaic should match the baseline");
  return check.ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
