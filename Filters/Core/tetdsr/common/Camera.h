// Pinhole and parallel cameras with vtkCamera's conventions, and one ray per pixel centre.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include <algorithm>
#include <cmath>

namespace tetdsr
{

struct Camera
{
  glm::dvec3 position{ 0.0, 0.0, 1.0 };
  glm::dvec3 focalPoint{ 0.0, 0.0, 0.0 };
  glm::dvec3 viewUp{ 0.0, 1.0, 0.0 };
  double viewAngleDegrees = 30.0; ///< vertical, as vtkCamera's default
  bool parallelProjection = false;
  double parallelScale = 1.0; ///< half the image height in world units (parallel projection)
};

/// A camera that sees the whole box, placed the way vtkRenderer::ResetCamera places its
/// default camera: looking down -z at the box centre from a distance where the bounding sphere
/// fits the (vertical, or for aspect < 1 horizontal) view angle.
inline Camera resetCamera(const double bounds[6], double aspect)
{
  const glm::dvec3 lo(bounds[0], bounds[2], bounds[4]);
  const glm::dvec3 hi(bounds[1], bounds[3], bounds[5]);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  double radius = 0.5 * glm::length(hi - lo);
  if (radius == 0.0)
  {
    radius = 0.5; // a single point: any positive size
  }
  Camera camera;
  double angle = glm::radians(camera.viewAngleDegrees);
  if (aspect < 1.0)
  {
    angle = 2.0 * std::atan(std::tan(0.5 * angle) * aspect);
  }
  const double distance = radius / std::sin(0.5 * angle);
  camera.focalPoint = centre;
  camera.position = centre + glm::dvec3(0.0, 0.0, distance);
  camera.parallelScale = radius;
  return camera;
}

struct Ray
{
  glm::dvec3 origin;
  glm::dvec3 direction; ///< unit length
};

inline bool isFinite(const glm::dvec3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// `v` scaled to unit length without overflow or underflow in the squared length (components
/// up to the largest double, down to subnormals); 0 for a zero or non-finite vector.
inline glm::dvec3 unitVector(const glm::dvec3& v)
{
  if (!isFinite(v))
  {
    return glm::dvec3(0.0); // (std::max below would not see a NaN component)
  }
  const double largest = std::max({ std::abs(v.x), std::abs(v.y), std::abs(v.z) });
  if (!(largest > 0.0) || !std::isfinite(largest))
  {
    return glm::dvec3(0.0);
  }
  const glm::dvec3 scaled = v / largest; // largest component is now +-1: no overflow below
  return scaled / glm::length(scaled);
}

/// Why a camera cannot make rays (None: it can).
enum class CameraProblem
{
  None,
  NonFinite,          ///< a NaN or Inf in position, focal point, view up, angle or scale
  CoincidentPoints,   ///< position equals focal point
  ViewUpParallel,     ///< view up is zero or parallel to the view direction
  AngleOutOfRange,    ///< view angle outside (0, 180) degrees, or parallel scale <= 0
  SingularProjection  ///< an explicit projection matrix that cannot be inverted
};

/// A readable sentence for a camera problem.
inline const char* describe(CameraProblem problem)
{
  switch (problem)
  {
    case CameraProblem::NonFinite:
      return "the camera has a NaN or Inf in its position, focal point, view up, view angle or "
             "parallel scale";
    case CameraProblem::CoincidentPoints:
      return "the camera's position equals its focal point";
    case CameraProblem::ViewUpParallel:
      return "the camera's view up is zero or parallel to its direction of view";
    case CameraProblem::AngleOutOfRange:
      return "the camera's view angle is outside (0, 180) degrees or its parallel scale is not "
             "positive";
    case CameraProblem::SingularProjection:
      return "the camera's projection matrix is singular or not finite";
    case CameraProblem::None:
    default:
      return "the camera is valid";
  }
}

/// One ray per pixel centre. Pixel (i, j) with j = 0 the bottom row maps to normalised device
/// coordinates x = 2(i+0.5)/width - 1, y = 2(j+0.5)/height - 1.
///
/// From a Camera: perspective rays start at the camera position; parallel rays start on the
/// camera plane, so the ray parameter is the distance from the camera (plane).
/// From an inverse projection (normalised device coordinates, z in [-1, 1], to world, as the
/// inverse of vtkCamera's composite projection): rays run from the near plane (z = -1) towards
/// the far plane (z = 1), so explicit and off-axis projections (tiles, stereo) work; the ray
/// parameter is the distance from the near plane. The far plane may be at infinity (w = 0 there:
/// an infinite-far-plane matrix, or a far / near ratio so large that the matrix rounds to one):
/// the direction is taken from homogeneous coordinates, never from the far point itself.
class RayGenerator
{
public:
  RayGenerator(const Camera& camera, int width, int height)
    : Width_(width)
    , Height_(height)
    , Parallel_(camera.parallelProjection)
    , Position_(camera.position)
  {
    // unitVector: the difference of far-apart points may overflow a plain length.
    Forward_ = unitVector(camera.focalPoint - camera.position);
    Right_ = unitVector(glm::cross(Forward_, unitVector(camera.viewUp)));
    Up_ = glm::cross(Right_, Forward_);
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    const double halfHeight = camera.parallelProjection
      ? camera.parallelScale
      : std::tan(0.5 * glm::radians(camera.viewAngleDegrees));
    HalfWidth_ = halfHeight * aspect;
    HalfHeight_ = halfHeight;
    // Each column's and row's part of a ray's offset, computed once (pixelRay adds them).
    ColumnOffsets_.resize(static_cast<std::size_t>(std::max(width, 0)));
    for (int i = 0; i < width; ++i)
    {
      ColumnOffsets_[static_cast<std::size_t>(i)] = (ndcX(i) * HalfWidth_) * Right_;
    }
    RowOffsets_.resize(static_cast<std::size_t>(std::max(height, 0)));
    for (int j = 0; j < height; ++j)
    {
      RowOffsets_[static_cast<std::size_t>(j)] = (ndcY(j) * HalfHeight_) * Up_;
    }
  }

  RayGenerator(const glm::dmat4& ndcToWorld, int width, int height)
    : Width_(width)
    , Height_(height)
    , FromMatrix_(true)
    , NdcToWorld_(ndcToWorld)
  {
  }

  Ray pixelRay(int i, int j) const
  {
    if (FromMatrix_)
    {
      return matrixRay(ndcX(i), ndcY(j));
    }
    const glm::dvec3 offset =
      ColumnOffsets_[static_cast<std::size_t>(i)] + RowOffsets_[static_cast<std::size_t>(j)];
    if (Parallel_)
    {
      return { Position_ + offset, Forward_ };
    }
    return { Position_, glm::normalize(Forward_ + offset) };
  }

  /// The ray through a point of the image given in pixels, continuously: (x, y) = (i + 0.5,
  /// j + 0.5) is pixel (i, j)'s centre, and gives pixelRay(i, j) bit for bit. For picking at a
  /// display position.
  Ray displayRay(double x, double y) const
  {
    const double ndcx = 2.0 * x / Width_ - 1.0, ndcy = 2.0 * y / Height_ - 1.0;
    if (FromMatrix_)
    {
      return matrixRay(ndcx, ndcy);
    }
    const glm::dvec3 offset = (ndcx * HalfWidth_) * Right_ + (ndcy * HalfHeight_) * Up_;
    if (Parallel_)
    {
      return { Position_ + offset, Forward_ };
    }
    return { Position_, glm::normalize(Forward_ + offset) };
  }

  /// What, if anything, keeps `camera` from defining rays.
  static CameraProblem check(const Camera& camera)
  {
    const bool finite = isFinite(camera.position) && isFinite(camera.focalPoint) &&
      isFinite(camera.viewUp) && std::isfinite(camera.viewAngleDegrees) &&
      std::isfinite(camera.parallelScale);
    if (!finite)
    {
      return CameraProblem::NonFinite;
    }
    if (camera.position == camera.focalPoint)
    {
      return CameraProblem::CoincidentPoints;
    }
    const glm::dvec3 forward = unitVector(camera.focalPoint - camera.position);
    const glm::dvec3 right = glm::cross(forward, unitVector(camera.viewUp));
    // The sine of the angle between view up and direction: below 1e-6 the image's orientation
    // depends on rounding (a change of 1e-10 in the vectors turns it visibly).
    if (!(glm::length(right) > 1e-6))
    {
      return CameraProblem::ViewUpParallel;
    }
    const bool angleOk = camera.parallelProjection
      ? (camera.parallelScale > 0.0)
      : (camera.viewAngleDegrees > 0.0 && camera.viewAngleDegrees < 180.0);
    return angleOk ? CameraProblem::None : CameraProblem::AngleOutOfRange;
  }

private:
  double ndcX(int i) const { return 2.0 * (i + 0.5) / Width_ - 1.0; }
  double ndcY(int j) const { return 2.0 * (j + 0.5) / Height_ - 1.0; }

  /// The ray through normalised device coordinates (x, y): from the near plane's point n towards
  /// the far plane's f, both unprojected as homogeneous points N = (n w_N, w_N), F = (f w_F, w_F).
  /// f - n = (F.xyz w_N - N.xyz w_F) / (w_N w_F); both points lie in front of the eye, so w_N and
  /// w_F share a sign (or w_F = 0: the far plane at infinity, F a direction) and the numerator
  /// alone has the direction. It is finite for every such matrix, and continuous through w_F = 0
  /// (a w_F rounded to either side of 0 gives the same ray).
  Ray matrixRay(double x, double y) const
  {
    const glm::dvec4 nearPoint = NdcToWorld_ * glm::dvec4(x, y, -1.0, 1.0);
    const glm::dvec4 farPoint = NdcToWorld_ * glm::dvec4(x, y, 1.0, 1.0);
    return { glm::dvec3(nearPoint) / nearPoint.w,
      unitVector(glm::dvec3(farPoint) * nearPoint.w - glm::dvec3(nearPoint) * farPoint.w) };
  }

  int Width_;
  int Height_;
  bool Parallel_ = false;
  bool FromMatrix_ = false;
  glm::dvec3 Position_{ 0.0 };
  glm::dvec3 Forward_{ 0.0 }, Right_{ 0.0 }, Up_{ 0.0 };
  double HalfWidth_ = 0.0, HalfHeight_ = 0.0;
  std::vector<glm::dvec3> ColumnOffsets_, RowOffsets_;
  glm::dmat4 NdcToWorld_{ 1.0 };
};

/// Window depth, as OpenGL's depth buffer holds it: 0.5 z / w + 0.5 of each hit through
/// `toNdc` (the view's composite projection, from the rays' coordinates), clamped to [0, 1];
/// 1 for a miss (an infinite or NaN ray parameter). `depth` and `out` hold one value per pixel
/// of `rays`' image (row j from the bottom), `width` pixels a row; rows [rowBegin, rowEnd).
inline void windowDepths(const RayGenerator& rays, const glm::dmat4& toNdc, const double* depth,
  float* out, int width, int rowBegin, int rowEnd)
{
  for (int j = rowBegin; j < rowEnd; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
        static_cast<std::size_t>(i);
      float value = 1.0f;
      if (std::isfinite(depth[p]))
      {
        const Ray ray = rays.pixelRay(i, j);
        const glm::dvec4 clip = toNdc * glm::dvec4(ray.origin + depth[p] * ray.direction, 1.0);
        value = static_cast<float>(std::min(1.0, std::max(0.0, 0.5 * clip.z / clip.w + 0.5)));
      }
      out[p] = value;
    }
  }
}

} // namespace tetdsr
