// Independent truth for the image tests, written without the filter's code:
// - pixel rays from a vtkCamera, following the filter's documented pixel convention;
// - the exact first hit of a quadratic field: per cell, the quadratic polynomial through the
//   10 nodal values (a 10x10 monomial fit solved by VTK's LU with partial pivoting), its exact
//   restriction to the ray, roots in long double, inside-test with vtkTetra::BarycentricCoords;
// - the first hit on vtkContourFilter's triangles along the same ray (vtkOBBTree);
// and the baseline comparison of the filter's Colors image.
#ifndef TetDSRTestSupport_h
#define TetDSRTestSupport_h

#include "vtkCamera.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkImageExtractComponents.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkOBBTree.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTesting.h"
#include "vtkTetra.h"
#include "vtkTriangle.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <vector>

namespace tetdsr_truth
{

struct Ray
{
  std::array<double, 3> origin;
  std::array<double, 3> direction; // unit
};

/// Pixel (i, j) of a width x height image: ray through the pixel centre (see the filter's docs).
inline Ray PixelRay(vtkCamera* camera, int width, int height, int i, int j)
{
  double position[3], focal[3], up[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  camera->GetViewUp(up);
  double forward[3] = { focal[0] - position[0], focal[1] - position[1], focal[2] - position[2] };
  vtkMath::Normalize(forward);
  double right[3], trueUp[3];
  vtkMath::Cross(forward, up, right);
  vtkMath::Normalize(right);
  vtkMath::Cross(right, forward, trueUp);
  const double aspect = static_cast<double>(width) / height;
  const double halfHeight = camera->GetParallelProjection()
    ? camera->GetParallelScale()
    : std::tan(0.5 * vtkMath::RadiansFromDegrees(camera->GetViewAngle()));
  const double x = (2.0 * (i + 0.5) / width - 1.0) * halfHeight * aspect;
  const double y = (2.0 * (j + 0.5) / height - 1.0) * halfHeight;
  Ray ray;
  for (int a = 0; a < 3; ++a)
  {
    const double offset = x * right[a] + y * trueUp[a];
    ray.origin[a] = camera->GetParallelProjection() ? position[a] + offset : position[a];
    ray.direction[a] = camera->GetParallelProjection() ? forward[a] : forward[a] + offset;
  }
  vtkMath::Normalize(ray.direction.data());
  return ray;
}

/// The exact quadratic field of each VTK_QUADRATIC_TETRA cell, in monomials about its centroid.
class QuadraticTruth
{
public:
  QuadraticTruth(vtkUnstructuredGrid* mesh, vtkDataArray* values)
  {
    for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
    {
      if (mesh->GetCellType(c) != VTK_QUADRATIC_TETRA)
      {
        continue;
      }
      vtkNew<vtkIdList> ids;
      mesh->GetCellPoints(c, ids);
      Cell cell;
      cell.id = c;
      for (int k = 0; k < 4; ++k)
      {
        mesh->GetPoint(ids->GetId(k), cell.vertex[k].data());
      }
      for (int a = 0; a < 3; ++a)
      {
        cell.centre[a] = 0.25 *
          (cell.vertex[0][a] + cell.vertex[1][a] + cell.vertex[2][a] + cell.vertex[3][a]);
      }
      double rows[10][10], rhs[10];
      double* matrix[10];
      for (int n = 0; n < 10; ++n)
      {
        double p[3];
        mesh->GetPoint(ids->GetId(n), p);
        Monomials(p, cell.centre.data(), rows[n]);
        matrix[n] = rows[n];
        rhs[n] = values->GetComponent(ids->GetId(n), 0);
      }
      if (!vtkMath::SolveLinearSystem(matrix, rhs, 10))
      {
        continue;
      }
      std::copy(rhs, rhs + 10, cell.coefficient.begin());
      this->Cells.push_back(cell);
    }
  }

  /// First t >= 0 where the field equals iso; `grazing` = the smallest relative discriminant
  /// among the roots considered (near 0: a tangent ray).
  bool FirstHit(const Ray& ray, double iso, double& tHit, vtkIdType& cellHit, double& grazing) const
  {
    tHit = std::numeric_limits<double>::infinity();
    grazing = std::numeric_limits<double>::infinity();
    for (const Cell& cell : this->Cells)
    {
      long double a, b, c;
      cell.AlongRay(ray, a, b, c);
      c -= iso;
      long double roots[2];
      int count = 0;
      if (a == 0.0L)
      {
        if (b != 0.0L)
        {
          roots[count++] = -c / b;
        }
      }
      else
      {
        const long double disc = b * b - 4.0L * a * c;
        if (disc >= 0.0L)
        {
          const long double q = -0.5L * (b + std::copysign(std::sqrt(disc), b));
          roots[count++] = q / a;
          if (q != 0.0L)
          {
            roots[count++] = c / q;
          }
        }
        const double relative = static_cast<double>(std::fabs(disc) / (b * b + std::fabs(4.0L * a * c)));
        if (count > 0 || relative < 1e-6)
        {
          // only tangencies that could concern this cell matter; checked below with inside()
          double point[3];
          const long double tMin = -b / (2.0L * a);
          for (int k = 0; k < 3; ++k)
          {
            point[k] = ray.origin[k] + static_cast<double>(tMin) * ray.direction[k];
          }
          if (cell.Inside(point, 1e-6))
          {
            grazing = std::min(grazing, relative);
          }
        }
      }
      for (int r = 0; r < count; ++r)
      {
        // One Newton step in long double polishes the root.
        long double t = roots[r];
        const long double slope = 2.0L * a * t + b;
        if (slope != 0.0L)
        {
          t -= ((a * t + b) * t + c) / slope;
        }
        const double td = static_cast<double>(t);
        double point[3];
        for (int k = 0; k < 3; ++k)
        {
          point[k] = ray.origin[k] + td * ray.direction[k];
        }
        if (td >= 0.0 && td < tHit && cell.Inside(point, 1e-9))
        {
          tHit = td;
          cellHit = cell.id;
        }
      }
    }
    return tHit < std::numeric_limits<double>::infinity();
  }

  /// Gradient of the field of `cellId` at a point.
  void Gradient(vtkIdType cellId, const double x[3], double gradient[3]) const
  {
    for (const Cell& cell : this->Cells)
    {
      if (cell.id == cellId)
      {
        const double* k = cell.coefficient.data();
        const double p[3] = { x[0] - cell.centre[0], x[1] - cell.centre[1], x[2] - cell.centre[2] };
        gradient[0] = k[1] + 2 * k[4] * p[0] + k[7] * p[1] + k[9] * p[2];
        gradient[1] = k[2] + 2 * k[5] * p[1] + k[7] * p[0] + k[8] * p[2];
        gradient[2] = k[3] + 2 * k[6] * p[2] + k[8] * p[1] + k[9] * p[0];
        return;
      }
    }
  }

private:
  // 1, x, y, z, x^2, y^2, z^2, xy, yz, zx about `centre`.
  static void Monomials(const double p[3], const double centre[3], double m[10])
  {
    const double x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    const double values[10] = { 1.0, x, y, z, x * x, y * y, z * z, x * y, y * z, z * x };
    std::copy(values, values + 10, m);
  }

  struct Cell
  {
    vtkIdType id;
    std::array<std::array<double, 3>, 4> vertex;
    std::array<double, 3> centre;
    std::array<double, 10> coefficient;

    // f(o + t d) = a t^2 + b t + c, expanded from the monomials.
    void AlongRay(const Ray& ray, long double& a, long double& b, long double& c) const
    {
      const long double o[3] = { ray.origin[0] - centre[0], ray.origin[1] - centre[1],
        ray.origin[2] - centre[2] };
      const double* d = ray.direction.data();
      const double* k = coefficient.data();
      // Quadratic part Q(v) = k4 x^2 + k5 y^2 + k6 z^2 + k7 xy + k8 yz + k9 zx, bilinear form B.
      auto bilinear = [k](const long double u[3], const long double v[3]) {
        return k[4] * u[0] * v[0] + k[5] * u[1] * v[1] + k[6] * u[2] * v[2] +
          0.5L * k[7] * (u[0] * v[1] + u[1] * v[0]) + 0.5L * k[8] * (u[1] * v[2] + u[2] * v[1]) +
          0.5L * k[9] * (u[2] * v[0] + u[0] * v[2]);
      };
      const long double dl[3] = { d[0], d[1], d[2] };
      a = bilinear(dl, dl);
      b = 2.0L * bilinear(o, dl) + k[1] * dl[0] + k[2] * dl[1] + k[3] * dl[2];
      c = bilinear(o, o) + k[0] + k[1] * o[0] + k[2] * o[1] + k[3] * o[2];
    }

    bool Inside(const double point[3], double tolerance) const
    {
      double bary[4];
      double x0[3], x1[3], x2[3], x3[3], p[3];
      std::copy(vertex[0].begin(), vertex[0].end(), x0);
      std::copy(vertex[1].begin(), vertex[1].end(), x1);
      std::copy(vertex[2].begin(), vertex[2].end(), x2);
      std::copy(vertex[3].begin(), vertex[3].end(), x3);
      std::copy(point, point + 3, p);
      if (!vtkTetra::BarycentricCoords(p, x0, x1, x2, x3, bary))
      {
        return false;
      }
      return bary[0] >= -tolerance && bary[1] >= -tolerance && bary[2] >= -tolerance &&
        bary[3] >= -tolerance;
    }
  };
  std::vector<Cell> Cells;
};

/// First hit of a ray on a triangle surface (e.g. vtkContourFilter's output); false if none.
class TriangleHits
{
public:
  explicit TriangleHits(vtkPolyData* surface)
    : Surface(surface)
  {
    this->Empty = surface->GetNumberOfCells() == 0;
    if (!this->Empty)
    {
      this->Tree->SetDataSet(surface);
      this->Tree->BuildLocator();
    }
  }

  bool FirstHit(const Ray& ray, double farDistance, double& t)
  {
    double normal[3];
    return this->FirstHit(ray, farDistance, t, normal);
  }

  /// Also the unit normal of the triangle hit (its orientation is the triangle's).
  bool FirstHit(const Ray& ray, double farDistance, double& t, double normal[3])
  {
    if (this->Empty)
    {
      return false;
    }
    double end[3];
    for (int a = 0; a < 3; ++a)
    {
      end[a] = ray.origin[a] + farDistance * ray.direction[a];
    }
    vtkNew<vtkPoints> points;
    vtkNew<vtkIdList> cells;
    if (this->Tree->IntersectWithLine(ray.origin.data(), end, points, cells) == 0 ||
      points->GetNumberOfPoints() == 0)
    {
      return false;
    }
    t = std::numeric_limits<double>::infinity();
    vtkIdType nearest = -1;
    for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p)
    {
      double x[3];
      points->GetPoint(p, x);
      const double distance = std::sqrt(vtkMath::Distance2BetweenPoints(x, ray.origin.data()));
      if (distance < t)
      {
        t = distance;
        nearest = cells->GetId(p);
      }
    }
    vtkIdType count;
    const vtkIdType* ids;
    this->Surface->GetCellPoints(nearest, count, ids);
    double a[3], b[3], c[3];
    this->Surface->GetPoint(ids[0], a);
    this->Surface->GetPoint(ids[1], b);
    this->Surface->GetPoint(ids[2], c);
    vtkTriangle::ComputeNormal(a, b, c, normal);
    return true;
  }

private:
  vtkPolyData* Surface = nullptr;
  bool Empty;
  vtkNew<vtkOBBTree> Tree;
};

/// Per-pixel comparison of the filter's output with the truth and with contour triangles.
struct Comparison
{
  int truthPixels = 0;       ///< pixels where the exact surface is hit
  int oursPixels = 0;        ///< pixels the filter covers
  int contourPixels = 0;     ///< pixels vtkContourFilter's triangles cover
  int excluded = 0;          ///< pixels within the tangency band (not compared)
  int oursFalseHits = 0;     ///< we hit, truth does not
  int oursMisses = 0;        ///< truth hits, we do not
  int contourMisses = 0;     ///< truth hits, the contour does not
  int contourFalseHits = 0;  ///< the contour hits, truth does not
  double oursMaxDepthError = 0.0;    ///< relative to the scene diagonal
  double contourMaxDepthError = 0.0; ///< relative to the scene diagonal, where both hit
  double oursMaxNormalError = 0.0;   ///< radians
  int wrongCellIds = 0;
};

inline Comparison Compare(vtkImageData* image, vtkCamera* camera, const QuadraticTruth& truth,
  double iso, TriangleHits& contour, double sceneDiagonal)
{
  Comparison result;
  int dims[3];
  image->GetDimensions(dims);
  vtkDataArray* depth = image->GetPointData()->GetArray("Depth");
  vtkDataArray* normals = image->GetPointData()->GetArray("Normals");
  vtkDataArray* cellIds = image->GetPointData()->GetArray("CellId");
  const double far = 100.0 * sceneDiagonal + 1e3;
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const vtkIdType pixel = i + static_cast<vtkIdType>(j) * dims[0];
      const Ray ray = PixelRay(camera, dims[0], dims[1], i, j);
      double tTrue, grazing, tContour;
      vtkIdType cellTrue = -1;
      const bool truthHit = truth.FirstHit(ray, iso, tTrue, cellTrue, grazing);
      const bool contourHit = contour.FirstHit(ray, far, tContour);
      const double tOurs = depth->GetComponent(pixel, 0);
      const bool oursHit = std::isfinite(tOurs);
      result.truthPixels += truthHit;
      result.oursPixels += oursHit;
      result.contourPixels += contourHit;
      result.contourMisses += truthHit && !contourHit;
      result.contourFalseHits += contourHit && !truthHit;
      if (truthHit && contourHit)
      {
        result.contourMaxDepthError =
          std::max(result.contourMaxDepthError, std::abs(tContour - tTrue) / sceneDiagonal);
      }
      if (grazing < 1e-6)
      {
        ++result.excluded;
        continue;
      }
      result.oursFalseHits += oursHit && !truthHit;
      result.oursMisses += truthHit && !oursHit;
      if (!(oursHit && truthHit))
      {
        continue;
      }
      result.oursMaxDepthError =
        std::max(result.oursMaxDepthError, std::abs(tOurs - tTrue) / sceneDiagonal);
      result.wrongCellIds += static_cast<vtkIdType>(cellIds->GetComponent(pixel, 0)) != cellTrue;
      double point[3], gradient[3], normal[3];
      for (int a = 0; a < 3; ++a)
      {
        point[a] = ray.origin[a] + tTrue * ray.direction[a];
        normal[a] = normals->GetComponent(pixel, a);
      }
      truth.Gradient(cellTrue, point, gradient);
      result.oursMaxNormalError =
        std::max(result.oursMaxNormalError, vtkMath::AngleBetweenVectors(normal, gradient));
    }
  }
  return result;
}

inline void Print(const char* name, const Comparison& c)
{
  std::cout << name << ": exact surface covers " << c.truthPixels << " pixels ("
            << c.excluded << " within the tangency band, not compared)\n"
            << "  TetDSR:           " << c.oursPixels << " pixels, " << c.oursMisses
            << " missed, " << c.oursFalseHits << " false, max depth error "
            << c.oursMaxDepthError << " of the diagonal, max normal error "
            << c.oursMaxNormalError << " rad, " << c.wrongCellIds << " wrong cell ids\n"
            << "  vtkContourFilter: " << c.contourPixels << " pixels, " << c.contourMisses
            << " missed, " << c.contourFalseHits << " false, max depth error "
            << c.contourMaxDepthError << " of the diagonal\n";
}

/// Records failed expectations with their message; `ok` tells whether all held.
struct Checks
{
  bool ok = true;
  void operator()(bool condition, const char* what)
  {
    if (!condition)
    {
      std::cerr << "FAILED: " << what << "\n";
      ok = false;
    }
  }
};

/// Compares the RGB of the filter's Colors with the test's baseline PNG (-V); a missing
/// baseline fails and writes the image to the -T directory.
inline bool MatchesBaseline(int argc, char* argv[], vtkAlgorithm* caster)
{
  vtkNew<vtkImageExtractComponents> rgb;
  rgb->SetInputConnection(caster->GetOutputPort());
  rgb->SetComponents(0, 1, 2);
  vtkNew<vtkTesting> testing;
  for (int a = 0; a < argc; ++a)
  {
    testing->AddArgument(argv[a]);
  }
  return testing->RegressionTest(rgb, 0.05) == vtkTesting::PASSED;
}

} // namespace tetdsr_truth

#endif
