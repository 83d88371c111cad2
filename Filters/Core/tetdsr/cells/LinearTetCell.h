// The linear tetrahedron (VTK_TETRA, 4 nodes). A linear field is a quadratic whose mid-edge
// values are the means of their edges' ends, on straight edges: so the cell is completed to the
// quadratic tetrahedron's 10 nodes (mid-edge nodes at the midpoints, values the means) and every
// later step is QuadraticTetCell's, exact for it. The cell seam's steps (Cells.h).
#pragma once

#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/QuadraticTetCell.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace tetdsr
{

/// Every step but validate is QuadraticTetCell's (inherited), on the completed cell.
struct LinearTetCell : QuadraticTetCell
{
  static constexpr int kNodes = 4;

  /// The 6 mid-edge nodes from the 4 vertices: their edges' midpoints.
  static void complete(glm::dvec3 nodes[kCellNodes])
  {
    for (int e = 0; e < 6; ++e)
    {
      nodes[4 + e] = 0.5 * (nodes[kEdgeVertices[e][0]] + nodes[kEdgeVertices[e][1]]);
    }
  }

  /// The 6 mid-edge values from the 4 vertices': their means (a linear field on the edge).
  static void complete(double values[kCellNodes])
  {
    for (int e = 0; e < 6; ++e)
    {
      values[4 + e] = 0.5 * (values[kEdgeVertices[e][0]] + values[kEdgeVertices[e][1]]);
    }
  }

  /// validate: the straight quadratic's checks of the completed nodes (never kCurved: the
  /// mid-edge nodes are the midpoints exactly).
  static std::uint16_t validate(const glm::dvec3 nodes[kCellNodes], double pointRounding)
  {
    return QuadraticTetCell::validate(nodes, pointRounding);
  }
};

} // namespace tetdsr
