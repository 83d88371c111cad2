// TEMPORARY local placeholder (not committed): helper's branch curvedp provides the real one.
#pragma once
#include "tetdsr/Cells.h"
#include "tetdsr/HigherOrderTetCell.h"
namespace tetdsr {
template <int P> struct CurvedHigherOrderTetCell : HigherOrderTetCell<P> {
  static constexpr int kRecordNodes = 0;
  static std::uint16_t validate(const glm::dvec3*, std::uint16_t) { return kTangled; }
  static bool intersect(const glm::dvec3*, const double*, const IsoValues&, std::size_t, std::size_t, const Ray&, double, double, SurfaceHit&, bool&) { return false; }
  static constexpr int kRecordCoefficients = 0;
  static void record(const glm::dvec3*, const double*, CellRecord& cell, double* = nullptr) { cell.kind = CellRecord::Kind::Curved; }
};
}
