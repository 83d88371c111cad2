// How a cast smaller than its viewport (an interactive frame) is upsampled without blending
// across silhouettes: which neighbouring cast pixels show one surface, and which 2 x 2 blocks
// can be filtered as a whole. The faces draw with these (the mapper's quad shader reads both as
// textures); the rule itself is written only here.
#pragma once

#include "tetdsr/index/Scene.h" // ParallelFor

#include <cstdint>
#include <vector>

namespace tetdsr
{

/// The eight neighbour offsets (dx, dy) of a cast pixel, in the order of sameSurfaceMasks' bits:
/// bit k is offset kNeighbourOffsets[k]. (Row j counts from the bottom, as the window's rows.)
constexpr int kNeighbourOffsets[8][2] = { { -1, -1 }, { 0, -1 }, { 1, -1 }, { -1, 0 }, { 1, 0 },
  { -1, 1 }, { 0, 1 }, { 1, 1 } };

/// The bit of offset (dx, dy) (each in -1..1, not both 0), or -1.
constexpr int neighbourBit(int dx, int dy)
{
  const int k = (dy + 1) * 3 + (dx + 1);
  return (dx < -1 || dx > 1 || dy < -1 || dy > 1 || k == 4) ? -1 : (k < 4 ? k : k - 1);
}

/// Whether cast pixel n (window depth dn, below 1) and its neighbour n + o (depth dt) show one
/// surface, judged from the four window depths along the line through them (n - o, n, n + o,
/// n + 2o; `depthAt` gives 2 outside the image, a miss is 1). A continuous surface changes its
/// depth by similar steps from pixel to pixel; a silhouette or a depth discontinuity between n
/// and n + o is a step out of line with those on both sides of it (also for a feature one pixel
/// wide: the step beyond it is the other surface's own). So the step is one surface's when it
/// is at most twice the smaller step beside it (the tolerance scales with the local depth
/// slope: steep and flat surfaces alike), or, where the slope itself changes (near a depth
/// extremum the steps shrink towards 0), when the two second differences agree in sign and
/// size, as a smooth curve's do (a jump makes them opposite). A side that is a miss or outside
/// the image says nothing. 2^-20 covers the rounding of float depths (24-bit mantissa) below 1.
/// Single precision throughout, as the depths are stored.
bool sameSurface(float before, float dn, float dt, float after);

/// What the upsampling filter does in each 2 x 2 block of cast pixels: the block with lower-left
/// corner (i, j), -1 <= i < width and -1 <= j < height, its corners clamped to the image (as a
/// texture read clamped to its edge), is stored at ((j + 1) * (width + 1) + i + 1).
enum class UpsampleBlock : std::uint8_t
{
  Mixed = 0,   ///< a silhouette or a miss among its corners: each output pixel keeps only the
               ///< corners on its nearest corner's surface (the masks)
  Surface = 1, ///< every corner a hit and each on the same surface as each other: bilinear
  Miss = 2     ///< every corner a miss: nothing drawn
};

/// The upsampling's maps of one cast image (width x height window depths, row j from the
/// bottom, a miss 1):
/// - masks, per cast pixel: bit k set when the pixel is a hit and its neighbour at
///   kNeighbourOffsets[k] is inside the image, a hit, and on the same surface (sameSurface);
/// - blocks, per 2 x 2 block (UpsampleBlock's layout), its kind.
struct UpsampleMaps
{
  std::vector<std::uint8_t> masks;
  std::vector<std::uint8_t> blocks;
  std::vector<float> padded;          ///< (work space: the depths with a border of 2)
  std::vector<std::uint8_t> forward;  ///< (work space: the four forward directions' bits)
};

/// Fills `maps` for `depth` (width x height), rows on `parallelFor`'s threads.
void upsampleMaps(
  const float* depth, int width, int height, UpsampleMaps& maps, const ParallelFor& parallelFor);

} // namespace tetdsr
