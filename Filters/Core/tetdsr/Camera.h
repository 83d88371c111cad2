// Pinhole and parallel cameras with vtkCamera's conventions, and one ray per pixel centre.
#pragma once

#include <glm/glm.hpp>

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

/// Pixel (i, j) with j = 0 the bottom row maps to normalised device coordinates
/// x = 2(i+0.5)/width - 1, y = 2(j+0.5)/height - 1. Perspective rays start at the camera
/// position; parallel rays start on the camera plane, so the ray parameter is the depth.
class RayGenerator
{
public:
  RayGenerator(const Camera& camera, int width, int height)
    : Camera_(camera)
    , Width_(width)
    , Height_(height)
  {
    Forward_ = glm::normalize(camera.focalPoint - camera.position);
    Right_ = glm::normalize(glm::cross(Forward_, camera.viewUp));
    Up_ = glm::cross(Right_, Forward_);
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    const double halfHeight = camera.parallelProjection
      ? camera.parallelScale
      : std::tan(0.5 * glm::radians(camera.viewAngleDegrees));
    HalfWidth_ = halfHeight * aspect;
    HalfHeight_ = halfHeight;
  }

  Ray pixelRay(int i, int j) const
  {
    const double x = 2.0 * (i + 0.5) / Width_ - 1.0;
    const double y = 2.0 * (j + 0.5) / Height_ - 1.0;
    const glm::dvec3 offset = (x * HalfWidth_) * Right_ + (y * HalfHeight_) * Up_;
    if (Camera_.parallelProjection)
    {
      return { Camera_.position + offset, Forward_ };
    }
    return { Camera_.position, glm::normalize(Forward_ + offset) };
  }

  /// False when position, focal point and view up do not define a frame.
  static bool valid(const Camera& camera)
  {
    const glm::dvec3 forward = camera.focalPoint - camera.position;
    const glm::dvec3 right = glm::cross(forward, camera.viewUp);
    const bool angleOk = camera.parallelProjection
      ? (camera.parallelScale > 0.0)
      : (camera.viewAngleDegrees > 0.0 && camera.viewAngleDegrees < 180.0);
    return glm::length(forward) > 0.0 && glm::length(right) > 0.0 && angleOk &&
      std::isfinite(glm::dot(right, right));
  }

private:
  Camera Camera_;
  int Width_;
  int Height_;
  glm::dvec3 Forward_, Right_, Up_;
  double HalfWidth_, HalfHeight_;
};

} // namespace tetdsr
