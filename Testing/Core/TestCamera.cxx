// Rays from a projection matrix (RayGenerator's inverse-projection constructor, what the mapper
// casts with) against the pinhole camera they come from: finite far planes, the far plane at
// infinity (the explicit infinite-far-plane matrix, and vtkCamera's matrix at a far / near ratio
// of 1e17, which rounds to it), a negated matrix, and off-axis and parallel projections; the
// window depth of hits seen through the infinite-far-plane matrix.
#include "tetdsr/common/Camera.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace
{
constexpr int kWidth = 37, kHeight = 23;
const glm::dvec3 kEye(2.2, 1.6, 3.0);
const glm::dvec3 kTarget(0.05, -0.03, 0.02);
constexpr double kViewAngleDegrees = 30.0;

/// A matrix from its rows (as vtkMatrix4x4 and the papers write them).
glm::dmat4 fromRows(const double rows[4][4])
{
  glm::dmat4 m;
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      m[c][r] = rows[r][c];
    }
  }
  return m;
}

glm::dmat4 view()
{
  return glm::lookAt(kEye, kTarget, glm::dvec3(0.0, 1.0, 0.0));
}

double cotangentOfHalfAngle()
{
  return 1.0 / std::tan(0.5 * glm::radians(kViewAngleDegrees));
}

/// vtkCamera's perspective matrix (vtkPerspectiveTransform::SetupCamera/Frustum) for the clipping
/// range [near, far], with its own formulas: at far / near = 1e17, -(f + n) / (f - n) rounds to -1.
glm::dmat4 vtkPerspective(double near, double far)
{
  const double f = cotangentOfHalfAngle(), aspect = double(kWidth) / kHeight;
  const double rows[4][4] = { { f / aspect, 0, 0, 0 }, { 0, f, 0, 0 },
    { 0, 0, -(far + near) / (far - near), -2.0 * far * near / (far - near) }, { 0, 0, -1, 0 } };
  return fromRows(rows);
}

/// The perspective matrix whose far plane is at infinity: NDC z = 1 is a direction (w = 0).
glm::dmat4 infinitePerspective(double near)
{
  const double f = cotangentOfHalfAngle(), aspect = double(kWidth) / kHeight;
  const double rows[4][4] = { { f / aspect, 0, 0, 0 }, { 0, f, 0, 0 }, { 0, 0, -1, -2.0 * near },
    { 0, 0, -1, 0 } };
  return fromRows(rows);
}

/// The pinhole camera's own ray direction through pixel (i, j): forward plus the pixel centre's
/// offset on the plane at distance 1 (Camera.h's convention, built independently here).
glm::dvec3 pinholeDirection(int i, int j)
{
  const glm::dvec3 forward = glm::normalize(kTarget - kEye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0)));
  const glm::dvec3 up = glm::cross(right, forward);
  const double half = 1.0 / cotangentOfHalfAngle();
  const double x = (2.0 * (i + 0.5) / kWidth - 1.0) * half * kWidth / kHeight;
  const double y = (2.0 * (j + 0.5) / kHeight - 1.0) * half;
  return glm::normalize(forward + x * right + y * up);
}

/// Every pixel's ray from `worldToNdc` is finite and unit, starts on the near plane at the
/// pixel's NDC (x, y), and runs along the pinhole camera's ray; returns the largest angle (in
/// radians) between the two directions.
double checkAgainstPinhole(const glm::dmat4& worldToNdc, const char* what)
{
  const tetdsr::RayGenerator rays(glm::inverse(worldToNdc), kWidth, kHeight);
  double worst = 0.0;
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      EXPECT_TRUE(tetdsr::isFinite(ray.origin) && tetdsr::isFinite(ray.direction))
        << what << ": pixel (" << i << ", " << j << ") has a non-finite ray";
      EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-14) << what;
      const glm::dvec4 clip = worldToNdc * glm::dvec4(ray.origin, 1.0);
      EXPECT_NEAR(clip.z / clip.w, -1.0, 1e-9) << what << ": the ray starts on the near plane";
      EXPECT_NEAR(clip.x / clip.w, 2.0 * (i + 0.5) / kWidth - 1.0, 1e-9) << what;
      EXPECT_NEAR(clip.y / clip.w, 2.0 * (j + 0.5) / kHeight - 1.0, 1e-9) << what;
      const double sine = glm::length(glm::cross(ray.direction, pinholeDirection(i, j)));
      EXPECT_GT(glm::dot(ray.direction, pinholeDirection(i, j)), 0.0)
        << what << ": pixel (" << i << ", " << j << ")'s ray points backwards";
      worst = std::max(worst, sine);
      // displayRay at the pixel centre is pixelRay, bit for bit.
      const tetdsr::Ray same = rays.displayRay(i + 0.5, j + 0.5);
      EXPECT_EQ(same.origin, ray.origin) << what;
      EXPECT_EQ(same.direction, ray.direction) << what;
    }
  }
  return worst;
}
}

TEST(RayGenerator, FiniteFarPlaneRaysAreThePinholeRays)
{
  const double worst = checkAgainstPinhole(vtkPerspective(0.5, 40.0) * view(), "far 40");
  EXPECT_LT(worst, 1e-13) << "expected the pinhole camera's rays, got directions " << worst
                          << " rad apart";
}

TEST(RayGenerator, InfiniteFarPlaneRaysAreThePinholeRays)
{
  // Before: the far point was unprojected at w = 0 and every ray was NaN (nothing drawn).
  const glm::dmat4 worldToNdc = infinitePerspective(0.5) * view();
  const glm::dvec4 far = glm::inverse(worldToNdc) * glm::dvec4(0.2, -0.3, 1.0, 1.0);
  ASSERT_LT(std::abs(far.w), 1e-15) << "the matrix's far plane is at infinity";
  const double worst = checkAgainstPinhole(worldToNdc, "infinite far plane");
  EXPECT_LT(worst, 1e-13) << "expected the pinhole camera's rays, got directions " << worst
                          << " rad apart";
}

TEST(RayGenerator, FarOverNearOf1e17IsTheInfiniteFarPlane)
{
  // vtkCamera's matrix for the clipping range [1e-3, 1e14]: its third row rounds to (0, 0, -1,
  // -2e-3), the infinite-far-plane matrix's; w at NDC z = 1 is 0 or a rounding away from it.
  const glm::dmat4 rounded = vtkPerspective(1e-3, 1e14) * view();
  EXPECT_EQ(vtkPerspective(1e-3, 1e14)[2][2], -1.0);
  const double worst = checkAgainstPinhole(rounded, "far / near = 1e17");
  // (The inverse holds 1 / (2 near) = 500: its rounding is that much larger than at near 0.5.)
  EXPECT_LT(worst, 1e-12) << "expected the pinhole camera's rays, got directions " << worst
                          << " rad apart";
  // The same rays as the exact infinite-far-plane matrix of that near plane.
  const tetdsr::RayGenerator a(glm::inverse(rounded), kWidth, kHeight);
  const tetdsr::RayGenerator b(glm::inverse(infinitePerspective(1e-3) * view()), kWidth, kHeight);
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      EXPECT_LT(glm::length(a.pixelRay(i, j).direction - b.pixelRay(i, j).direction), 1e-13);
      EXPECT_LT(glm::length(a.pixelRay(i, j).origin - b.pixelRay(i, j).origin), 1e-12);
    }
  }
}

TEST(RayGenerator, NegatedMatrixGivesTheSameRays)
{
  // A homogeneous matrix and its negative are one projection (w < 0 at every point).
  const glm::dmat4 worldToNdc = infinitePerspective(0.5) * view();
  const tetdsr::RayGenerator a(glm::inverse(worldToNdc), kWidth, kHeight);
  const tetdsr::RayGenerator b(glm::inverse(-1.0 * worldToNdc), kWidth, kHeight);
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      EXPECT_LT(glm::length(a.pixelRay(i, j).direction - b.pixelRay(i, j).direction), 1e-14);
      EXPECT_LT(glm::length(a.pixelRay(i, j).origin - b.pixelRay(i, j).origin), 1e-14);
    }
  }
}

TEST(RayGenerator, OffAxisInfiniteFarPlaneAndParallel)
{
  // An asymmetric frustum with its far plane at infinity (the off-axis projection of a tracked
  // eye): each ray goes through its pixel's point on the near plane, from the eye.
  const double l = -0.1, r = 0.35, b = -0.25, t = 0.08, n = 0.6;
  const double rows[4][4] = { { 2 * n / (r - l), 0, (r + l) / (r - l), 0 },
    { 0, 2 * n / (t - b), (t + b) / (t - b), 0 }, { 0, 0, -1, -2 * n }, { 0, 0, -1, 0 } };
  const glm::dmat4 worldToNdc = fromRows(rows) * view();
  const tetdsr::RayGenerator rays(glm::inverse(worldToNdc), kWidth, kHeight);
  // Parallel: every ray has the view direction.
  const glm::dmat4 parallel = glm::ortho(-1.3, 0.7, -0.6, 0.9, 0.5, 30.0) * view();
  const tetdsr::RayGenerator parallelRays(glm::inverse(parallel), kWidth, kHeight);
  const glm::dvec3 forward = glm::normalize(kTarget - kEye);
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      const glm::dvec3 fromEye = glm::normalize(ray.origin - kEye);
      EXPECT_LT(glm::length(ray.direction - fromEye), 1e-12)
        << "pixel (" << i << ", " << j << "): expected the ray from the eye";
      EXPECT_LT(glm::length(parallelRays.pixelRay(i, j).direction - forward), 1e-14);
    }
  }
}

TEST(RayGenerator, WindowDepthThroughAnInfiniteFarPlane)
{
  // A hit at view distance d through the infinite-far-plane matrix of near plane n has NDC
  // z = 1 - 2 n / d, window depth 1 - n / d: finite, below 1 and increasing with d.
  const double near = 0.5;
  const glm::dmat4 worldToNdc = infinitePerspective(near) * view();
  const tetdsr::RayGenerator rays(glm::inverse(worldToNdc), kWidth, kHeight);
  const glm::dvec3 forward = glm::normalize(kTarget - kEye);
  std::vector<double> depth(static_cast<std::size_t>(kWidth) * kHeight);
  std::vector<double> distance(depth.size());
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * kWidth + i;
      depth[p] = 0.7 + 0.35 * i + 4.0 * j; // ray parameters up to about 100
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      distance[p] = glm::dot(ray.origin + depth[p] * ray.direction - kEye, forward);
    }
  }
  depth[3] = std::numeric_limits<double>::infinity(); // a miss
  std::vector<float> window(depth.size());
  tetdsr::windowDepths(rays, worldToNdc, depth.data(), window.data(), kWidth, 0, kHeight);
  for (std::size_t p = 0; p < depth.size(); ++p)
  {
    if (p == 3)
    {
      EXPECT_EQ(window[p], 1.0f) << "a miss is at the far plane";
      continue;
    }
    const double expected = 1.0 - near / distance[p];
    EXPECT_NEAR(window[p], expected, 1e-7) << "pixel " << p << " at view distance "
                                           << distance[p];
    EXPECT_LT(window[p], 1.0f);
  }
}
