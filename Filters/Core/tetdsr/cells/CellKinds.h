// Every kind of cell (Cells.h), and the one dispatch from a kind to its steps.
#pragma once

#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/CurvedHigherOrderTetCell.h"
#include "tetdsr/cells/CurvedTetCell.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/cells/HigherOrderTetCell.h"
#include "tetdsr/cells/LinearTetCell.h"
#include "tetdsr/cells/QuadraticTetCell.h"
#include "tetdsr/cells/WedgeCell.h"

namespace tetdsr
{

/// Runs `step` with an object of the cell kind's type (its steps are static: call them as
/// decltype(cell)::extent(...)). The one place a new kind joins the steps Scene dispatches.
template <typename Step>
decltype(auto) forKind(CellKind kind, Step&& step)
{
  switch (kind)
  {
    case CellKind::LinearTet:
      return step(LinearTetCell{});
    case CellKind::CurvedTet:
      return step(CurvedTetCell{});
    case CellKind::CubicTet:
      return step(HigherOrderTetCell<3>{});
    case CellKind::QuarticTet:
      return step(HigherOrderTetCell<4>{});
    case CellKind::CurvedCubicTet:
      return step(CurvedHigherOrderTetCell<3>{});
    case CellKind::CurvedQuarticTet:
      return step(CurvedHigherOrderTetCell<4>{});
    case CellKind::Hexahedron1:
      return step(HexahedronCell<1, false>{});
    case CellKind::Hexahedron2:
      return step(HexahedronCell<2, false>{});
    case CellKind::Hexahedron3:
      return step(HexahedronCell<3, false>{});
    case CellKind::Hexahedron4:
      return step(HexahedronCell<4, false>{});
    case CellKind::CurvedHexahedron1:
      return step(HexahedronCell<1, true>{});
    case CellKind::CurvedHexahedron2:
      return step(HexahedronCell<2, true>{});
    case CellKind::CurvedHexahedron3:
      return step(HexahedronCell<3, true>{});
    case CellKind::CurvedHexahedron4:
      return step(HexahedronCell<4, true>{});
    case CellKind::Wedge1:
      return step(WedgeCell<1>{});
    case CellKind::Wedge2:
      return step(WedgeCell<2>{});
    case CellKind::Wedge3:
      return step(WedgeCell<3>{});
    case CellKind::Wedge4:
      return step(WedgeCell<4>{});
    case CellKind::QuadraticTet:
      break;
  }
  return step(QuadraticTetCell{});
}


} // namespace tetdsr
