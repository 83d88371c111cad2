// Hard cases for the ray caster, and their independent truth.
//
// A quadratic polynomial sampled at the 10 nodes of straight-sided quadratic tets is represented
// exactly, so the true first hit of a ray is the first root t >= 0 of the quadratic
// f(o + t d) - iso, computed here from the polynomial's own coefficients in long double, that lies
// in the meshed domain (a box or a single tet). None of the ray caster's code is used.
//
// Excluded band (stated, counted): a pixel is not compared when
// - its ray grazes the surface: it meets it within kGrazingCosine of tangency
//   (|grad f . d| <= kGrazingCosine |grad f|, where the depth is ill-conditioned), or passes it
//   closer than kSilhouetteBand * diagonal without meeting it (may count as touching), or
// - the true root lies within kSilhouetteBand * diagonal of where the ray enters or leaves the
//   domain, or the ray crosses the domain over less than that (the domain's silhouette).
#pragma once

#include "LatticeMesh.h"

#include "tetdsr/common/Camera.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace tetdsr_test
{

constexpr double kGrazingCosine = 1e-5;
constexpr double kSilhouetteBand = 1e-9;

/// f(x) = (x - centre)^T A (x - centre) + b.(x - centre) + c.
struct Quadric
{
  glm::dmat3 A{ 0.0 };
  glm::dvec3 b{ 0.0 };
  double c = 0.0;
  glm::dvec3 centre{ 0.0 };

  double operator()(const glm::dvec3& x) const
  {
    const glm::dvec3 y = x - centre;
    return glm::dot(y, A * y) + glm::dot(b, y) + c;
  }
  glm::dvec3 gradient(const glm::dvec3& x) const { return 2.0 * (A * (x - centre)) + b; }
};

/// The meshed domain: an axis-aligned box, or one tetrahedron.
struct Domain
{
  bool isTet = false;
  glm::dvec3 lo{ 0.0 }, hi{ 0.0 };
  glm::dvec3 tet[4];

  double diagonal() const
  {
    if (!isTet)
      return glm::length(hi - lo);
    double d = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        d = std::max(d, glm::length(tet[i] - tet[j]));
    return d;
  }

  /// Parameter interval of the ray inside the domain (long double); false if none.
  bool clip(const tetdsr::Ray& ray, long double& tIn, long double& tOut) const
  {
    tIn = 0.0L;
    tOut = std::numeric_limits<long double>::infinity();
    auto halfSpace = [&](long double value, long double slope) {
      // keep {t : value + slope t >= 0}
      if (slope > 0)
        tIn = std::max(tIn, -value / slope);
      else if (slope < 0)
        tOut = std::min(tOut, -value / slope);
      else if (value < 0)
        tOut = -1.0L;
    };
    if (!isTet)
    {
      for (int a = 0; a < 3; ++a)
      {
        halfSpace((long double)ray.origin[a] - lo[a], ray.direction[a]);
        halfSpace((long double)hi[a] - ray.origin[a], -(long double)ray.direction[a]);
      }
    }
    else
    {
      for (int k = 0; k < 4; ++k)
      {
        // plane through the three other vertices, oriented towards vertex k
        const glm::dvec3& p0 = tet[(k + 1) % 4];
        const glm::dvec3& p1 = tet[(k + 2) % 4];
        const glm::dvec3& p2 = tet[(k + 3) % 4];
        long double e1[3], e2[3], n[3];
        for (int a = 0; a < 3; ++a)
        {
          e1[a] = (long double)p1[a] - p0[a];
          e2[a] = (long double)p2[a] - p0[a];
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        long double side = 0, value = 0, slope = 0;
        for (int a = 0; a < 3; ++a)
        {
          side += n[a] * ((long double)tet[k][a] - p0[a]);
          value += n[a] * ((long double)ray.origin[a] - p0[a]);
          slope += n[a] * (long double)ray.direction[a];
        }
        if (side < 0)
        {
          value = -value;
          slope = -slope;
        }
        halfSpace(value, slope);
      }
    }
    return tIn <= tOut;
  }
};

struct TruthHit
{
  bool hit = false;
  bool excluded = false;
  double t = 0.0;
};

/// The true first crossing of f = iso along the ray within the domain.
inline TruthHit trueFirstHit(
  const Quadric& f, double iso, const Domain& domain, const tetdsr::Ray& ray)
{
  TruthHit truth;
  long double tIn, tOut;
  const long double band = kSilhouetteBand * domain.diagonal();
  if (!domain.clip(ray, tIn, tOut))
    return truth;
  if (tOut - tIn <= band)
  {
    truth.excluded = true; // grazes the domain
    return truth;
  }
  // f(o + t d) = a t^2 + b t + c in long double, about the quadric's centre.
  long double y[3], d[3];
  for (int i = 0; i < 3; ++i)
  {
    y[i] = (long double)ray.origin[i] - f.centre[i];
    d[i] = ray.direction[i];
  }
  long double a = 0, b = 0, c = (long double)f.c - iso;
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      const long double Aij = f.A[j][i]; // glm is column-major: A[col][row]
      a += d[i] * Aij * d[j];
      b += 2.0L * d[i] * Aij * y[j];
      c += y[i] * Aij * y[j];
    }
    b += (long double)f.b[i] * d[i];
    c += (long double)f.b[i] * y[i];
  }
  long double roots[2];
  int count = 0;
  if (a == 0.0L)
  {
    if (b != 0.0L)
      roots[count++] = -c / b;
    else if (c == 0.0L)
      roots[count++] = tIn; // the field equals the iso-value along the whole ray
  }
  else
  {
    const long double disc = b * b - 4.0L * a * c;
    if (disc < 0.0L)
    {
      // A near miss: how far the closest approach (t*) is from the surface.
      const long double tangent = -b / (2.0L * a);
      const glm::dvec3 p = ray.origin + static_cast<double>(tangent) * ray.direction;
      const double gap = static_cast<double>(std::fabs(disc / (4.0L * a))) /
        std::max(glm::length(f.gradient(p)), std::numeric_limits<double>::min());
      if (tangent >= tIn - band && tangent <= tOut + band && gap <= kSilhouetteBand * domain.diagonal())
      {
        truth.excluded = true;
        return truth;
      }
    }
    if (disc >= 0.0L)
    {
      const long double q = -0.5L * (b + std::copysign(std::sqrt(disc), b));
      roots[count++] = q / a;
      if (q != 0.0L)
        roots[count++] = c / q;
    }
  }
  std::sort(roots, roots + count);
  for (int r = 0; r < count; ++r)
  {
    long double t = roots[r];
    const long double slope = 2.0L * a * t + b;
    if (slope != 0.0L)
      t -= ((a * t + b) * t + c) / slope; // one Newton step polishes the root
    if (t < tIn - band || t > tOut + band)
      continue;
    if (std::fabs(t - tIn) <= band || std::fabs(t - tOut) <= band)
    {
      if (!(a == 0.0L && b == 0.0L))
      {
        truth.excluded = true; // on the domain's silhouette
        return truth;
      }
    }
    const glm::dvec3 g = f.gradient(ray.origin + static_cast<double>(t) * ray.direction);
    const bool everywhere = a == 0.0L && b == 0.0L; // f = iso along the whole ray
    if (!everywhere && std::abs(glm::dot(g, ray.direction)) <= kGrazingCosine * glm::length(g))
    {
      truth.excluded = true; // grazing (or a double root): the depth is ill-conditioned
      return truth;
    }
    truth.hit = true;
    truth.t = static_cast<double>(t);
    return truth;
  }
  return truth;
}

/// Per-case figures.
struct Figures
{
  std::string name;
  int rays = 0;
  int compared = 0;
  int excluded = 0;
  int misses = 0;    ///< truth hits, we do not
  int falseHits = 0; ///< we hit, truth does not
  double maxDepthError = 0.0;  ///< relative to the domain's diagonal
  double maxNormalError = 0.0; ///< radians, where |grad f| >= 1e-3 of its typical size
  int hits = 0;
};

/// A case: a mesh carrying a quadric, an iso-value, the domain, and cameras.
struct Case
{
  std::string name;
  LatticeMesh mesh;
  Quadric field;
  double iso = 0.0;
  Domain domain;
  std::vector<tetdsr::Camera> cameras;
  int pixels = 40; ///< per side, per camera
};

/// What is compared: `firstHit(ray, camera, i, j, t, unitNormal)` for pixel (i, j) of camera
/// number `camera` returns whether it hit, with the depth and unit normal.
using HitFunction =
  std::function<bool(const tetdsr::Ray&, std::size_t, int, int, double&, glm::dvec3&)>;

/// Runs `firstHit` (the code under test) over a case's pixels and compares with the truth.
inline Figures evaluate(const Case& c, const HitFunction& firstHit)
{
  Figures figures;
  figures.name = c.name;
  const double diagonal = c.domain.diagonal();
  // Typical gradient size: at the domain's centre and corners.
  double typicalGradient = 0.0;
  const glm::dvec3 mid = c.domain.isTet
    ? 0.25 * (c.domain.tet[0] + c.domain.tet[1] + c.domain.tet[2] + c.domain.tet[3])
    : 0.5 * (c.domain.lo + c.domain.hi);
  typicalGradient = std::max(typicalGradient, glm::length(c.field.gradient(mid)));
  for (int k = 0; k < 8; ++k)
  {
    const glm::dvec3 corner = c.domain.isTet
      ? c.domain.tet[k % 4]
      : glm::dvec3(k & 1 ? c.domain.hi.x : c.domain.lo.x, k & 2 ? c.domain.hi.y : c.domain.lo.y,
          k & 4 ? c.domain.hi.z : c.domain.lo.z);
    typicalGradient = std::max(typicalGradient, glm::length(c.field.gradient(corner)));
  }
  for (std::size_t k = 0; k < c.cameras.size(); ++k)
  {
    const tetdsr::RayGenerator rays(c.cameras[k], c.pixels, c.pixels);
    for (int j = 0; j < c.pixels; ++j)
      for (int i = 0; i < c.pixels; ++i)
      {
        const tetdsr::Ray ray = rays.pixelRay(i, j);
        ++figures.rays;
        const TruthHit truth = trueFirstHit(c.field, c.iso, c.domain, ray);
        if (truth.excluded)
        {
          ++figures.excluded;
          continue;
        }
        ++figures.compared;
        double t;
        glm::dvec3 normal;
        const bool hit = firstHit(ray, k, i, j, t, normal);
        figures.misses += truth.hit && !hit;
        figures.falseHits += hit && !truth.hit;
        if (!(hit && truth.hit))
          continue;
        ++figures.hits;
        figures.maxDepthError = std::max(figures.maxDepthError, std::abs(t - truth.t) / diagonal);
        const glm::dvec3 g = c.field.gradient(ray.origin + truth.t * ray.direction);
        if (glm::length(g) >= 1e-3 * typicalGradient)
        {
          const double angle =
            std::atan2(glm::length(glm::cross(normal, g)), glm::dot(normal, g));
          figures.maxNormalError = std::max(figures.maxNormalError, angle);
        }
      }
  }
  return figures;
}

/// The core's answer for a case (no VTK).
inline Figures evaluateScene(const Case& c)
{
  const tetdsr::Scene scene(c.mesh.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ c.iso }));
  return evaluate(c, [&](const tetdsr::Ray& ray, std::size_t, int, int, double& t, glm::dvec3& n) {
    tetdsr::SurfaceHit hit;
    if (!surface.firstHit(ray, hit))
      return false;
    t = hit.t;
    const double length = glm::length(hit.gradient);
    n = length > 0.0 ? hit.gradient / length : glm::dvec3(0.0);
    return true;
  });
}

/// Cameras around a box or tet: perspective and parallel, from `count` random directions.
inline std::vector<tetdsr::Camera> camerasAround(
  const glm::dvec3& centre, double radius, int count, std::mt19937_64& rng)
{
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<tetdsr::Camera> cameras;
  for (int k = 0; k < count; ++k)
  {
    glm::dvec3 direction(normal(rng), normal(rng), normal(rng));
    direction = glm::normalize(direction);
    tetdsr::Camera camera;
    camera.focalPoint = centre;
    camera.position = centre + 3.0 * radius * direction;
    camera.viewUp = std::abs(direction.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    camera.viewAngleDegrees = 45.0;
    camera.parallelProjection = k % 2 == 1;
    camera.parallelScale = 1.05 * radius;
    cameras.push_back(camera);
  }
  return cameras;
}

inline Quadric randomQuadric(std::mt19937_64& rng, const glm::dvec3& centre, double size)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Quadric q;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      q.A[i][j] = q.A[j][i] = u(rng) / (size * size);
  q.b = glm::dvec3(u(rng), u(rng), u(rng)) / size;
  q.centre = centre;
  return q;
}

/// A lattice case over the box origin + [0, size]^3 with n^3 cubes.
inline Case latticeCase(const std::string& name, int n, const glm::dvec3& origin,
  const glm::dvec3& size, const Quadric& field, double iso, std::mt19937_64& rng, int cameras = 4)
{
  Case c;
  c.name = name;
  c.mesh = makeLattice(n, glm::dvec3(0.0), 1.0);
  c.mesh.mapVertices([&](const glm::dvec3& p, const std::array<int, 3>&) { return origin + p * size; });
  c.field = field;
  c.iso = iso;
  c.mesh.sample([&](const glm::dvec3& x) { return field(x); });
  c.domain.lo = origin;
  c.domain.hi = origin + size;
  c.cameras = camerasAround(origin + 0.5 * size, 0.5 * glm::length(size), cameras, rng);
  return c;
}

/// One tetrahedron (10 nodes) as the whole mesh.
inline Case tetCase(const std::string& name, const glm::dvec3 v[4], const Quadric& field,
  double iso, std::mt19937_64& rng)
{
  Case c;
  c.name = name;
  static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  for (int k = 0; k < 10; ++k)
  {
    const glm::dvec3 p = k < 4 ? v[k] : 0.5 * (v[edges[k - 4][0]] + v[edges[k - 4][1]]);
    c.mesh.points.insert(c.mesh.points.end(), { p.x, p.y, p.z });
    c.mesh.cellNodes.push_back(k);
  }
  c.field = field;
  c.iso = iso;
  c.mesh.sample([&](const glm::dvec3& x) { return field(x); });
  c.domain.isTet = true;
  for (int k = 0; k < 4; ++k)
    c.domain.tet[k] = v[k];
  const glm::dvec3 centre = 0.25 * (v[0] + v[1] + v[2] + v[3]);
  double radius = 0.0;
  for (int k = 0; k < 4; ++k)
    radius = std::max(radius, glm::length(v[k] - centre));
  c.cameras = camerasAround(centre, radius, 6, rng);
  return c;
}

/// The named hard cases (deterministic).
inline std::vector<Case> hardCases()
{
  std::mt19937_64 rng(2024);
  std::vector<Case> cases;
  const glm::dvec3 zero(0.0), unit(1.0);
  auto quadric = [](glm::dmat3 A, glm::dvec3 b, double c, glm::dvec3 centre) {
    Quadric q;
    q.A = A;
    q.b = b;
    q.c = c;
    q.centre = centre;
    return q;
  };
  const glm::dvec3 mid(0.5);
  const glm::dmat3 I(1.0);
  // Saddles and hyperboloids (A indefinite); iso-values through the saddle point and off it.
  cases.push_back(latticeCase("saddle x^2 - y^2 = 0", 4, zero, unit,
    quadric(glm::dmat3(1, 0, 0, 0, -1, 0, 0, 0, 0), zero, 0.0, mid), 0.0, rng));
  cases.push_back(latticeCase("saddle xy = 0.02", 4, zero, unit,
    quadric(glm::dmat3(0, 0.5, 0, 0.5, 0, 0, 0, 0, 0), zero, 0.0, mid), 0.02, rng));
  cases.push_back(latticeCase("hyperboloid, one sheet", 4, zero, unit,
    quadric(glm::dmat3(1, 0, 0, 0, 1, 0, 0, 0, -1), zero, 0.0, mid), 0.04, rng));
  cases.push_back(latticeCase("hyperboloid, two sheets", 4, zero, unit,
    quadric(glm::dmat3(1, 0, 0, 0, 1, 0, 0, 0, -1), zero, 0.0, mid), -0.04, rng));
  // Spheres: a thin shell crossed twice within cells, and spheres far smaller than a cell.
  cases.push_back(latticeCase("sphere r = 0.3 (thin shell in cells)", 3, zero, unit,
    quadric(I, zero, 0.0, glm::dvec3(0.52, 0.47, 0.5)), 0.09, rng));
  for (double ratio : { 1e-1, 1e-2, 1e-3 })
  {
    // Centre inside one cell, away from its faces; cameras zoomed onto the sphere.
    const glm::dvec3 centre(0.5 + 0.03, 0.5 + 0.2, 0.5 + 0.11);
    const double cell = 1.0 / 4.0, r = ratio * cell;
    Case c = latticeCase("sphere r = " + std::to_string(ratio).substr(0, 5) + " cell", 4, zero,
      unit, quadric(I, zero, 0.0, centre), r * r, rng);
    c.cameras = camerasAround(centre, 1.2 * r, 4, rng);
    cases.push_back(c);
  }
  // Linear along the rays (a = 0): a parabolic cylinder z = x^2 seen along z, and a linear field
  // whose iso-value equals nodal values, so the surface lies on cell faces (roots at entry/exit).
  {
    Case c = latticeCase("parabolic cylinder, rays along its axis (a = 0)", 4, zero, unit,
      quadric(glm::dmat3(1, 0, 0, 0, 0, 0, 0, 0, 0), glm::dvec3(0, 0, -1), 0.0, mid), 0.0, rng);
    for (tetdsr::Camera& camera : c.cameras)
    {
      camera.position = camera.focalPoint + glm::dvec3(0.0, 0.0, 2.0);
      camera.viewUp = glm::dvec3(0, 1, 0);
    }
    cases.push_back(c);
  }
  cases.push_back(latticeCase("surface on cell faces (iso = nodal values)", 4, zero, unit,
    quadric(glm::dmat3(0.0), glm::dvec3(0, 0, 1), 0.0, zero), 0.5, rng));
  cases.push_back(latticeCase("iso-value equal to a vertex value of the sphere", 4, zero, unit,
    quadric(I, zero, 0.0, mid), 0.125, rng)); // |(0.25, 0.25, 0)|^2 = 0.125: lattice nodes on it
  // Coordinates offset and scaled.
  cases.push_back(latticeCase("sphere, coordinates offset by 1e6", 3, glm::dvec3(1e6), unit,
    quadric(I, zero, 0.0, glm::dvec3(1e6 + 0.52)), 0.09, rng));
  cases.push_back(latticeCase("sphere, domain scaled to 1e-6", 3, zero, glm::dvec3(1e-6),
    quadric(I * 1e12, zero, 0.0, glm::dvec3(0.52e-6)), 0.09, rng));
  cases.push_back(latticeCase("sphere, domain scaled to 1e6", 3, zero, glm::dvec3(1e6),
    quadric(I * 1e-12, zero, 0.0, glm::dvec3(0.52e6)), 0.09, rng));
  // Anisotropic cells: slabs (aspect 1e4) and needles (aspect 1e4).
  cases.push_back(latticeCase("slab cells, aspect 1e4", 3, zero, glm::dvec3(1, 1, 1e-4),
    quadric(glm::dmat3(1, 0, 0, 0, 1, 0, 0, 0, 1e8), zero, 0.0, glm::dvec3(0.5, 0.5, 0.5e-4)), 0.09,
    rng));
  {
    Case c = latticeCase("needle cells, aspect 1e4", 3, zero, glm::dvec3(1e-4, 1e-4, 1),
      quadric(glm::dmat3(1e8, 0, 0, 0, 1e8, 0, 0, 0, 1), zero, 0.0, glm::dvec3(0.5e-4, 0.5e-4, 0.5)),
      0.09, rng);
    // Zoom onto the needles, where the surface's top is: pixels must be finer than a cell.
    c.cameras = camerasAround(glm::dvec3(0.5e-4, 0.5e-4, 0.75), 2e-4, 4, rng);
    cases.push_back(c);
  }
  // Single badly shaped tets: sliver (4 vertices near a plane, projecting to a quadrilateral),
  // needle, cap (one vertex near the opposite face's interior); random quadrics through them.
  {
    const glm::dvec3 sliver[4] = { { 0, 0, 0 }, { 1, 1, 0 }, { 1, 0, 1e-4 }, { 0, 1, 1e-4 } };
    const glm::dvec3 needle[4] = { { 0, 0, 0 }, { 1e-4, 0, 0 }, { 0, 1e-4, 0 }, { 0, 0, 1 } };
    const glm::dvec3 cap[4] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0.3, 0.3, 1e-4 } };
    const std::pair<const char*, const glm::dvec3*> tets[] = { { "sliver tet, aspect 1e4", sliver },
      { "needle tet, aspect 1e4", needle }, { "cap tet, aspect 1e4", cap } };
    for (const auto& [name, v] : tets)
    {
      const glm::dvec3 centre = 0.25 * (v[0] + v[1] + v[2] + v[3]);
      // A sphere through the centroid, steep across the thin direction.
      const Quadric q = quadric(I, zero, 0.0, centre + glm::dvec3(0.1, -0.05, 0.02));
      Case c = tetCase(name, v, q, q(centre), rng);
      // Zoom onto the centroid (on the surface), at the scale of the cell's thin direction.
      c.cameras = camerasAround(centre, 3e-4, 6, rng);
      cases.push_back(c);
    }
  }
  return cases;
}

/// Randomised: a jittered lattice, a random quadric, random cameras (perspective and parallel).
inline Case randomCase(unsigned seed, int pixels)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 3;
  Quadric q = randomQuadric(rng, glm::dvec3(0.5), 1.0);
  Case c = latticeCase("random seed " + std::to_string(seed), n, glm::dvec3(0.0), glm::dvec3(1.0),
    q, 0.0, rng, 4);
  // Jitter interior vertices by up to 0.3 of a cell (the domain stays the unit box).
  const double cell = 1.0 / n;
  c.mesh.mapVertices([&](const glm::dvec3& p, const std::array<int, 3>& key) {
    bool interior = true;
    for (int a = 0; a < 3; ++a)
      interior = interior && key[a] % 2 == 0 && key[a] > 0 && key[a] < 2 * n;
    return interior ? p + 0.3 * cell * glm::dvec3(u(rng), u(rng), u(rng)) : p;
  });
  // The iso-value of a random interior point, so the surface crosses the domain.
  const glm::dvec3 inside(0.5 + 0.4 * u(rng), 0.5 + 0.4 * u(rng), 0.5 + 0.4 * u(rng));
  c.iso = q(inside);
  c.mesh.sample([&](const glm::dvec3& x) { return q(x); });
  c.pixels = pixels;
  return c;
}

} // namespace tetdsr_test
