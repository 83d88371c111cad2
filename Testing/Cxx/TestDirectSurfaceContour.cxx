// The exact isosurface as data, where vtkContourFilter finds nothing: two concentric spheres of
// the exactly quadratic field |x - c|^2 - r^2 strictly inside one quadratic tetrahedron (no
// nodal value straddles either iso-value). vtkDirectSurfaceContour must give two closed
// surfaces (every edge used by two triangles, Euler characteristic 2 each) whose vertices lie on
// the analytic spheres, whose triangles stay within the distance bound, and whose area, volume
// and point-array integrals agree with the analytic ones within the reported error estimates.
// All truth is analytic (the sphere, its area, volume and moments); nothing is compared with a
// stored output.
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkContourFilter.h"
#include "vtkDataArray.h"
#include "vtkDirectSurfaceContour.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTestErrorObserver.h"
#include "vtkTetra.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
/// Records failed expectations with "expected X, got Y"; `ok` tells whether all held.
struct Checks
{
  bool ok = true;
  void operator()(bool condition, const std::string& what)
  {
    if (!condition)
    {
      std::cerr << "FAILED: " << what << "\n";
      ok = false;
    }
  }
};

template <typename... Parts>
std::string Text(const Parts&... parts)
{
  std::ostringstream stream;
  stream.precision(17);
  (stream << ... << parts);
  return stream.str();
}

double FieldValue(vtkFieldData* fieldData, const char* name, vtkIdType tuple, int component = 0)
{
  vtkDataArray* array = fieldData->GetArray(name);
  return array && tuple < array->GetNumberOfTuples() ? array->GetComponent(tuple, component)
                                                     : std::nan("");
}
}

int TestDirectSurfaceContour(int, char*[])
{
  Checks check;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(TETDSR_DATA_DIR "/sphere_in_cell.vtu");
  reader->Update();
  vtkNew<vtkUnstructuredGrid> mesh;
  mesh->DeepCopy(reader->GetOutput());
  double centre[3];
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = mesh->GetFieldData()->GetArray("SphereCentre")->GetComponent(a, 0);
  }
  const double radius = mesh->GetFieldData()->GetArray("SphereRadius")->GetComponent(0, 0);

  // More point arrays: the position (interpolated exactly by the straight quadratic cells, and
  // with the analytic surface moment 4 pi r^2 c), and a string array, which is not numeric and
  // must be left out.
  vtkNew<vtkDoubleArray> position;
  position->SetName("position");
  position->SetNumberOfComponents(3);
  vtkNew<vtkStringArray> labels;
  labels->SetName("labels");
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    position->InsertNextTuple(mesh->GetPoint(p));
    labels->InsertNextValue("node " + std::to_string(p));
  }
  mesh->GetPointData()->AddArray(position);
  mesh->GetPointData()->AddArray(labels);

  // The mesh's volume from its straight cells' corners (the cube [-1, 1]^3, cut into 6 tets).
  double meshVolume = 0.0;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    vtkNew<vtkIdList> ids;
    mesh->GetCellPoints(c, ids);
    double x[4][3];
    for (int k = 0; k < 4; ++k)
    {
      mesh->GetPoint(ids->GetId(k), x[k]);
    }
    meshVolume += std::abs(vtkTetra::ComputeVolume(x[0], x[1], x[2], x[3]));
  }

  // vtkContourFilter: no cell's nodal values straddle either iso-value, so nothing.
  // The two iso-values: the sphere of radius r (0) and the one of radius r/2 (-3/4 r^2).
  const double isoValues[2] = { 0.0, -0.75 * radius * radius };
  const double radii[2] = { radius, 0.5 * radius };
  vtkNew<vtkContourFilter> contour;
  contour->SetInputData(mesh);
  contour->SetValue(0, isoValues[0]);
  contour->SetValue(1, isoValues[1]);
  contour->Update();
  check(contour->GetOutput()->GetNumberOfCells() == 0,
    Text("vtkContourFilter: expected 0 triangles (the missing-surface case), got ",
      contour->GetOutput()->GetNumberOfCells()));

  vtkNew<vtkTest::ErrorObserver> observer;
  vtkNew<vtkDirectSurfaceContour> exact;
  exact->AddObserver(vtkCommand::ErrorEvent, observer);
  exact->AddObserver(vtkCommand::WarningEvent, observer);
  exact->SetInputData(mesh);
  exact->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "sphere");
  exact->SetValue(0, isoValues[0]);
  exact->SetValue(1, isoValues[1]);
  // 2e-2 of the diagonal (0.33 r): the certified bound is conservative, and the default 1e-3
  // gives 783,066 triangles here (2 minutes); the checks below hold for any bound.
  const double relativeTolerance = 2e-2;
  exact->SetTolerance(relativeTolerance);
  exact->Update();
  check(!observer->GetError() && !observer->GetWarning(),
    Text("no error or warning expected, got: ", observer->GetErrorMessage(),
      observer->GetWarningMessage()));
  vtkPolyData* surface = exact->GetOutput();
  vtkFieldData* fieldData = surface->GetFieldData();
  const vtkIdType triangles = surface->GetNumberOfCells();
  std::cout << "vtkDirectSurfaceContour: " << surface->GetNumberOfPoints() << " points, "
            << triangles << " triangles, distance bound " << exact->GetDistanceBound() << "\n";
  check(triangles > 100, Text("expected more than 100 triangles, got ", triangles));

  // The distance bound: the tolerance times the valid cells' box diagonal (every cell is valid;
  // the core's box may be rounded outward, to single precision at most).
  const double diagonal = mesh->GetLength();
  check(std::abs(exact->GetDistanceBound() - relativeTolerance * diagonal) <=
      1e-6 * relativeTolerance * diagonal,
    Text("distance bound: expected ", relativeTolerance * diagonal, ", got ",
      exact->GetDistanceBound()));
  check(FieldValue(fieldData, "DistanceBound", 0) == exact->GetDistanceBound(),
    "field data DistanceBound should equal GetDistanceBound()");
  check(exact->GetUnresolvedSubcells() == 0,
    Text("expected 0 unresolved subcells, got ", exact->GetUnresolvedSubcells()));
  check(fieldData->GetArray("SizeCertifiedSubcells") != nullptr,
    "field data SizeCertifiedSubcells expected");
  for (const char* name : { "UnresolvedSubcells", "BoundaryEdges", "NonManifoldEdges" })
  {
    check(FieldValue(fieldData, name, 0) == 0.0,
      Text(name, ": expected 0, got ", FieldValue(fieldData, name, 0)));
  }
  check(FieldValue(fieldData, "Subcells", 0) > 0.0, "Subcells: expected more than 0");
  const double largestBound = FieldValue(fieldData, "LargestCertifiedBound", 0);
  check(largestBound >= 0.0 && largestBound <= exact->GetDistanceBound(),
    Text("LargestCertifiedBound: expected within [0, ", exact->GetDistanceBound(), "], got ",
      largestBound));

  // Closed: every edge used by exactly two triangles; two spheres: V - E + F = 2 + 2.
  vtkDataArray* cellIds = surface->GetCellData()->GetArray("vtkOriginalCellIds");
  vtkDataArray* isoValueOf = surface->GetCellData()->GetArray("IsoValue");
  check(cellIds && vtkIdTypeArray::SafeDownCast(cellIds) && isoValueOf,
    "cell data vtkOriginalCellIds (vtkIdTypeArray) and IsoValue expected");
  if (!check.ok)
  {
    return EXIT_FAILURE;
  }
  std::map<std::pair<vtkIdType, vtkIdType>, int> edgeUses;
  std::vector<int> surfaceOfPoint(surface->GetNumberOfPoints(), -1);
  int wrongCells = 0, wrongIsoValues = 0, mixedTriangles = 0, notTriangles = 0;
  double farthestCentroid = 0.0; // how far inside its sphere a triangle's centroid lies at most
  for (vtkIdType t = 0; t < triangles; ++t)
  {
    vtkIdType count;
    const vtkIdType* ids;
    surface->GetCellPoints(t, count, ids);
    if (count != 3)
    {
      ++notTriangles;
      continue;
    }
    const double iso = isoValueOf->GetComponent(t, 0);
    const int which = iso == isoValues[0] ? 0 : iso == isoValues[1] ? 1 : -1;
    wrongIsoValues += which < 0;
    wrongCells += cellIds->GetComponent(t, 0) != 0.0; // both spheres lie in cell 0
    double centroid[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      const std::pair<vtkIdType, vtkIdType> edge(
        std::min(ids[k], ids[(k + 1) % 3]), std::max(ids[k], ids[(k + 1) % 3]));
      ++edgeUses[edge];
      mixedTriangles += surfaceOfPoint[ids[k]] >= 0 && surfaceOfPoint[ids[k]] != which;
      surfaceOfPoint[ids[k]] = which;
      double x[3];
      surface->GetPoint(ids[k], x);
      for (int a = 0; a < 3; ++a)
      {
        centroid[a] += x[a] / 3.0;
      }
    }
    if (which >= 0)
    {
      // The centroid is a point of the triangle: within the distance bound of the sphere.
      const double distance =
        std::abs(std::sqrt(vtkMath::Distance2BetweenPoints(centroid, centre)) - radii[which]);
      farthestCentroid = std::max(farthestCentroid, distance);
    }
  }
  check(notTriangles == 0, Text("expected triangles only, got ", notTriangles, " other cells"));
  check(wrongCells == 0, Text("expected every triangle in cell 0, got ", wrongCells, " elsewhere"));
  check(wrongIsoValues == 0, Text(wrongIsoValues, " triangles with an IsoValue not asked for"));
  check(mixedTriangles == 0, Text(mixedTriangles, " vertices shared by both surfaces"));
  int edgesNotShared = 0;
  for (const auto& uses : edgeUses)
  {
    edgesNotShared += uses.second != 2;
  }
  check(edgesNotShared == 0,
    Text("closed surface: expected every edge used by 2 triangles, ", edgesNotShared, " are not"));
  const vtkIdType euler = surface->GetNumberOfPoints() - static_cast<vtkIdType>(edgeUses.size()) +
    triangles;
  check(euler == 4, Text("two spheres: expected V - E + F = 4, got ", euler));
  check(farthestCentroid <= exact->GetDistanceBound(),
    Text("triangle centroids: expected within the distance bound ", exact->GetDistanceBound(),
      " of the sphere, got ", farthestCentroid));

  // Vertices on the analytic spheres, with the exact normals and the arrays interpolated.
  vtkDataArray* normals = surface->GetPointData()->GetNormals();
  vtkDataArray* sphereValues = surface->GetPointData()->GetArray("sphere");
  vtkDataArray* positions = surface->GetPointData()->GetArray("position");
  check(normals && std::string(normals->GetName()) == "Normals",
    "active normals named Normals expected");
  check(sphereValues && positions && positions->GetNumberOfComponents() == 3,
    "point arrays sphere and position (3 components) expected");
  check(!surface->GetPointData()->GetAbstractArray("labels"),
    "the string array labels should be left out");
  if (!check.ok)
  {
    return EXIT_FAILURE;
  }
  double radiusError = 0.0, normalError = 0.0, valueError = 0.0, positionError = 0.0;
  for (vtkIdType p = 0; p < surface->GetNumberOfPoints(); ++p)
  {
    const int which = surfaceOfPoint[p];
    if (which < 0)
    {
      continue;
    }
    double x[3], n[3], outward[3];
    surface->GetPoint(p, x);
    normals->GetTuple(p, n);
    const double distance = std::sqrt(vtkMath::Distance2BetweenPoints(x, centre));
    radiusError = std::max(radiusError, std::abs(distance - radii[which]) / radius);
    for (int a = 0; a < 3; ++a)
    {
      outward[a] = (x[a] - centre[a]) / distance; // the gradient 2 (x - c), normalised
      normalError = std::max(normalError, std::abs(n[a] - outward[a]));
      positionError = std::max(positionError, std::abs(positions->GetComponent(p, a) - x[a]));
    }
    const double exactValue = distance * distance - radius * radius;
    valueError = std::max(valueError, std::abs(sphereValues->GetComponent(p, 0) - exactValue));
  }
  check(radiusError <= 1e-9,
    Text("vertices: expected on the spheres within 1e-9 r, got ", radiusError, " r"));
  check(normalError <= 1e-9,
    Text("normals: expected the unit gradient within 1e-9, got ", normalError));
  check(valueError <= 1e-12,
    Text("interpolated sphere field: expected |x - c|^2 - r^2 within 1e-12, got ", valueError));
  check(positionError <= 1e-12,
    Text("interpolated position: expected the vertex within 1e-12, got ", positionError));

  // Orientation: each triangle's normal toward higher values, outward here, so the triangles'
  // signed volume (divergence theorem) is the enclosed polyhedron's, positive.
  double signedVolume[2] = { 0.0, 0.0 };
  for (vtkIdType t = 0; t < triangles; ++t)
  {
    vtkIdType count;
    const vtkIdType* ids;
    surface->GetCellPoints(t, count, ids);
    double a[3], b[3], c[3], bc[3];
    surface->GetPoint(ids[0], a);
    surface->GetPoint(ids[1], b);
    surface->GetPoint(ids[2], c);
    for (int k = 0; k < 3; ++k)
    {
      a[k] -= centre[k];
      b[k] -= centre[k];
      c[k] -= centre[k];
    }
    vtkMath::Cross(b, c, bc);
    signedVolume[surfaceOfPoint[ids[0]]] += vtkMath::Dot(a, bc) / 6.0;
  }

  // The integrals, per iso-value, against the analytic sphere.
  const double pi = vtkMath::Pi();
  for (int i = 0; i < 2; ++i)
  {
    const double r = radii[i];
    const double area = 4.0 * pi * r * r;
    const double ball = 4.0 / 3.0 * pi * r * r * r;
    check(FieldValue(fieldData, "IsoValues", i) == isoValues[i],
      Text("IsoValues[", i, "]: expected ", isoValues[i], ", got ",
        FieldValue(fieldData, "IsoValues", i)));
    check(FieldValue(fieldData, "Area", i) == exact->GetArea(i) &&
        FieldValue(fieldData, "AreaError", i) == exact->GetAreaError(i) &&
        FieldValue(fieldData, "Volume", i) == exact->GetVolume(i) &&
        FieldValue(fieldData, "VolumeError", i) == exact->GetVolumeError(i),
      Text("field data Area, AreaError, Volume, VolumeError [", i, "] should equal the getters"));
    const double areaOff = std::abs(exact->GetArea(i) - area);
    check(areaOff <= exact->GetAreaError(i) + 1e-6 * area,
      Text("area [", i, "]: expected 4 pi r^2 = ", area, " within the reported error ",
        exact->GetAreaError(i), " + 1e-6 relative, got ", exact->GetArea(i)));
    // The region where the field >= the iso-value: the mesh outside the ball.
    const double volume = meshVolume - ball;
    const double volumeOff = std::abs(exact->GetVolume(i) - volume);
    check(volumeOff <= exact->GetVolumeError(i) + 1e-6 * meshVolume,
      Text("volume [", i, "]: expected ", volume, " within the reported error ",
        exact->GetVolumeError(i), " + 1e-6 of the mesh's, got ", exact->GetVolume(i)));
    const double flatArea = FieldValue(fieldData, "FlatArea", i);
    check(flatArea > 0.0 && flatArea < area,
      Text("flat area [", i, "]: expected in (0, ", area, "), got ", flatArea));
    // The polyhedron's volume differs from the ball's by at most its area times the bound.
    check(std::abs(signedVolume[i] - ball) <= area * exact->GetDistanceBound(),
      Text("signed volume of the triangles [", i, "]: expected ", ball, " within ",
        area * exact->GetDistanceBound(), ", got ", signedVolume[i]));
    // The sphere's moment: the integral of the position over it is 4 pi r^2 c.
    for (int a = 0; a < 3; ++a)
    {
      const double integral = FieldValue(fieldData, "position Integral", i, a);
      const double error = FieldValue(fieldData, "position IntegralError", i, a);
      check(std::abs(integral - area * centre[a]) <= error + 1e-6 * area,
        Text("position integral [", i, "][", a, "]: expected ", area * centre[a],
          " within the reported error ", error, " + 1e-6 relative, got ", integral));
    }
    std::cout << "iso-value " << isoValues[i] << ": area " << exact->GetArea(i) << " (exact "
              << area << ", off " << areaOff << ", estimated " << exact->GetAreaError(i)
              << "), volume " << exact->GetVolume(i) << " (exact " << volume << ", off "
              << volumeOff << ", estimated " << exact->GetVolumeError(i) << ")\n";
  }
  check(std::isnan(exact->GetArea(2)) && std::isnan(exact->GetVolume(-1)),
    "the integrals of an iso-value not asked for should be NaN");
  check(!fieldData->GetArray("labels Integral"), "no integral of the string array expected");

  // The same surface on one thread.
  vtkNew<vtkDirectSurfaceContour> serial;
  serial->SetInputData(mesh);
  serial->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "sphere");
  serial->SetValue(0, isoValues[0]);
  serial->SetValue(1, isoValues[1]);
  serial->SetTolerance(relativeTolerance);
  serial->SetNumberOfThreads(1);
  serial->Update();
  vtkPolyData* serialSurface = serial->GetOutput();
  bool samePoints = serialSurface->GetNumberOfPoints() == surface->GetNumberOfPoints() &&
    serialSurface->GetNumberOfCells() == triangles;
  for (vtkIdType p = 0; samePoints && p < surface->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3];
    surface->GetPoint(p, x);
    serialSurface->GetPoint(p, y);
    samePoints = x[0] == y[0] && x[1] == y[1] && x[2] == y[2];
  }
  check(samePoints,
    Text("one thread: expected the same points and triangles, got ",
      serialSurface->GetNumberOfPoints(), " points and ", serialSurface->GetNumberOfCells(),
      " triangles (all threads: ", surface->GetNumberOfPoints(), ", ", triangles, ")"));

  // An absolute tolerance replaces the relative one, and holds; without integrals the field
  // data keep the surface's counts and bounds only.
  exact->SetAbsoluteTolerance(0.3 * radius);
  exact->SetComputeIntegrals(false);
  exact->Update();
  check(exact->GetDistanceBound() == 0.3 * radius,
    Text("absolute tolerance: expected the distance bound ", 0.3 * radius, ", got ",
      exact->GetDistanceBound()));
  check(std::isnan(exact->GetArea(0)), "without integrals GetArea should be NaN");
  check(!exact->GetOutput()->GetFieldData()->GetArray("Area") &&
      exact->GetOutput()->GetFieldData()->GetArray("DistanceBound"),
    "without integrals: DistanceBound expected, Area not");
  double farthest = 0.0;
  for (vtkIdType t = 0; t < exact->GetOutput()->GetNumberOfCells(); ++t)
  {
    vtkIdType count;
    const vtkIdType* ids;
    exact->GetOutput()->GetCellPoints(t, count, ids);
    const int which =
      exact->GetOutput()->GetCellData()->GetArray("IsoValue")->GetComponent(t, 0) == 0.0 ? 0 : 1;
    double centroid[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      double x[3];
      exact->GetOutput()->GetPoint(ids[k], x);
      for (int a = 0; a < 3; ++a)
      {
        centroid[a] += x[a] / 3.0;
      }
    }
    farthest = std::max(farthest,
      std::abs(std::sqrt(vtkMath::Distance2BetweenPoints(centroid, centre)) - radii[which]));
  }
  check(exact->GetOutput()->GetNumberOfCells() > 0 && farthest <= 0.3 * radius,
    Text("absolute tolerance 0.3 r: expected triangles with centroids within ", 0.3 * radius,
      " of the spheres, got ", exact->GetOutput()->GetNumberOfCells(), " triangles, ", farthest));

  // The core refuses a negative tolerance: an error, and an empty output. (The executive's
  // report of the failure is observed too: the test fails on any error printed.)
  observer->Clear();
  vtkNew<vtkTest::ErrorObserver> executiveObserver;
  exact->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveObserver);
  exact->SetTolerance(-1.0);
  exact->SetAbsoluteTolerance(0.0);
  exact->Update();
  check(observer->GetError(), "a negative tolerance: expected an error, got none");
  const std::string message = observer->GetErrorMessage();
  check(message.find("tolerance (-1") != std::string::npos,
    Text("a negative tolerance: expected the core's error naming it, got ", message));
  check(exact->GetOutput()->GetNumberOfPoints() == 0,
    Text("a negative tolerance: expected an empty output, got ",
      exact->GetOutput()->GetNumberOfPoints(), " points"));
  return check.ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
