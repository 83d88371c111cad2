// VTK's arbitrary-order tetrahedra (VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON) of order P:
// where their nodes sit, and their conversion to Bernstein-Bezier form (TetBernstein.h).
//
// A cell of order P has latticeCount(P) nodes (4, 10, 20, 35 for P = 1..4). Node n sits at the
// barycentric point alpha_n / P of the reference tetrahedron, alpha_n a multi-index of degree P;
// VTK's order of the n (vtkHigherOrderTetra): the 4 vertices, the P - 1 nodes of each edge
// (0,1) (1,2) (2,0) (0,3) (1,3) (2,3) from its first vertex to its second, each face's interior
// nodes (faces (0,1,3) (1,2,3) (0,2,3) (0,1,2); for P = 4 the 3 of a face ordered as its inner
// triangle's corners, given below), then the interior (one node for P = 4). Testing/Cxx checks
// this against vtkLagrangeTetra's and vtkBezierTetra's own parametric coordinates and
// interpolation functions for every P.
//
// A Lagrange cell's nodes are values of the map and field at those points; a Bezier cell's are
// their Bernstein coefficients (control points). The core works on the second: a Lagrange cell is
// converted once by the inverse of the matrix B_b(alpha_a / P) (its infinity norm is 3, 10 and 35
// for P = 2, 3, 4: the conversion's rounding stays within 35 eps of the nodal values).
// "Bezier layout": Bernstein coefficients in VTK's node order (vertices first, as every kind's
// arrays have them).
#pragma once

#include "tetdsr/common/CellTypes.h"
#include "tetdsr/math/TetBernstein.h"

#include <algorithm>
#include <array>
#include <type_traits>
#include <cmath>
#include <utility>

namespace tetdsr
{

/// The highest order of Lagrange and Bezier tetrahedra the core reads from its input.
constexpr int kMaxTetOrder = kMaxReadOrder;
/// The most nodes (or tensor form coefficients) a cell of the core's kinds has: a Lagrange
/// hexahedron's of the highest order, (kMaxReadOrder + 1)^3.
constexpr int kMaxCellNodes = (kMaxReadOrder + 1) * (kMaxReadOrder + 1) * (kMaxReadOrder + 1);
static_assert(kMaxCellNodes >= latticeCount(kMaxTetOrder), "a tetrahedron's nodes fit");

/// Runs `step` with std::integral_constant<int, P> for a higher tetrahedron order P (3 or 4);
/// the one dispatch from a run-time order to the templates of that order.
template <typename Step>
decltype(auto) forHigherOrder(int order, Step&& step)
{
  static_assert(kMaxTetOrder == 4, "a case per order");
  if (order == 3)
  {
    return step(std::integral_constant<int, 3>{});
  }
  return step(std::integral_constant<int, 4>{}); // (cellLayout reads no other: TestCellTypes)
}

/// The order P of a tetrahedron with `nodes` nodes: the P with (P + 1)(P + 2)(P + 3) / 6 == nodes
/// (any P, as VTK reads them); 0 if `nodes` is no tetrahedral number.
inline int tetOrderOf(long long nodes)
{
  // (Beyond 2^50 ids, 8 PiB of connectivity, none is taken: the product below stays in range.)
  if (nodes < 4 || nodes > (1LL << 50))
  {
    return 0;
  }
  // P is within 2 of the cube root of 6 nodes (the product lies between P^3 and (P + 3)^3).
  const auto estimate = static_cast<long long>(std::cbrt(6.0 * static_cast<double>(nodes)));
  for (long long p = std::max(1LL, estimate - 3); p <= estimate + 1; ++p)
  {
    if ((p + 1) * (p + 2) * (p + 3) / 6 == nodes)
    {
      return static_cast<int>(p);
    }
  }
  return 0;
}

template <int P>
struct HigherOrderTet
{
  static constexpr int kNodes = latticeCount(P);

  /// For each VTK node n, the canonical position (TetBernstein.h) of its multi-index alpha_n.
  static constexpr std::array<int, kNodes> makeLatticeOfNode()
  {
    std::array<int, kNodes> at{};
    int n = 0;
    auto put = [&](int a0, int a1, int a2, int a3) {
      (void)a0;
      at[n++] = latticeIndex(P, a1, a2, a3);
    };
    auto vertexPoint = [](int v, int weight, int (&alpha)[4]) { alpha[v] += weight; };
    for (int v = 0; v < 4; ++v)
    {
      int alpha[4] = { 0, 0, 0, 0 };
      vertexPoint(v, P, alpha);
      put(alpha[0], alpha[1], alpha[2], alpha[3]);
    }
    constexpr int kEdges[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
    for (const auto& edge : kEdges)
    {
      for (int k = 1; k < P; ++k)
      {
        int alpha[4] = { 0, 0, 0, 0 };
        alpha[edge[0]] = P - k;
        alpha[edge[1]] = k;
        put(alpha[0], alpha[1], alpha[2], alpha[3]);
      }
    }
    // Face interiors: for P = 3 one node (1 at each of the face's corners); for P = 4 three, each
    // 2 at one corner and 1 at the others, the corners in this order per face.
    constexpr int kFaceCorners[4][3] = { { 0, 1, 3 }, { 2, 3, 1 }, { 0, 3, 2 }, { 0, 2, 1 } };
    for (const auto& face : kFaceCorners)
    {
      const int inner = P - 3; // the inner triangle's order: its nodes are the face's interior
      if (inner == 0)
      {
        int alpha[4] = { 0, 0, 0, 0 };
        alpha[face[0]] = alpha[face[1]] = alpha[face[2]] = 1;
        put(alpha[0], alpha[1], alpha[2], alpha[3]);
      }
      else if (inner == 1)
      {
        for (int corner = 0; corner < 3; ++corner)
        {
          int alpha[4] = { 0, 0, 0, 0 };
          alpha[face[0]] = alpha[face[1]] = alpha[face[2]] = 1;
          alpha[face[corner]] += 1;
          put(alpha[0], alpha[1], alpha[2], alpha[3]);
        }
      }
    }
    if (P == 4)
    {
      put(1, 1, 1, 1);
    }
    return at;
  }

  static constexpr std::array<int, kNodes> kLatticeOfNode = makeLatticeOfNode();

  /// VTK order to canonical order (a permutation), `components` values per node.
  template <typename T>
  static void toLattice(const T* vtkOrder, T* canonical)
  {
    for (int n = 0; n < kNodes; ++n)
    {
      canonical[kLatticeOfNode[n]] = vtkOrder[n];
    }
  }

  /// The barycentric point of VTK node n.
  static void nodePoint(int n, double L[4])
  {
    const auto& alpha = Lattice<P>::kTables.alpha[kLatticeOfNode[n]];
    for (int k = 0; k < 4; ++k)
    {
      L[k] = static_cast<double>(alpha[k]) / P;
    }
  }

  /// The Bernstein polynomial of canonical position `at` at L: multinomial * prod L_k^alpha_k.
  static double basisAt(int at, const double L[4])
  {
    const auto& alpha = Lattice<P>::kTables.alpha[at];
    double value = Lattice<P>::kTables.multinomial[at];
    for (int k = 0; k < 4; ++k)
    {
      value *= std::pow(L[k], alpha[k]);
    }
    return value;
  }

  /// The inverse of a kNodes x kNodes matrix: [a | I] reduced to [I | a^-1] by Gauss-Jordan
  /// elimination with partial pivoting (rows whose pivot column is already 0 are left alone, so
  /// a unit row stays exact).
  static void invert(const double a[kNodes][kNodes], double inverse[kNodes][kNodes])
  {
    double m[kNodes][2 * kNodes];
    for (int r = 0; r < kNodes; ++r)
    {
      for (int c = 0; c < kNodes; ++c)
      {
        m[r][c] = a[r][c];
        m[r][kNodes + c] = r == c ? 1.0 : 0.0;
      }
    }
    for (int col = 0; col < kNodes; ++col)
    {
      int pivot = col;
      for (int r = col + 1; r < kNodes; ++r)
      {
        pivot = std::abs(m[r][col]) > std::abs(m[pivot][col]) ? r : pivot;
      }
      std::swap(m[col], m[pivot]);
      const double p = m[col][col];
      for (double& entry : m[col])
      {
        entry /= p;
      }
      for (int r = 0; r < kNodes; ++r)
      {
        if (r != col && m[r][col] != 0.0)
        {
          const double factor = m[r][col];
          for (int c = 0; c < 2 * kNodes; ++c)
          {
            m[r][c] -= factor * m[col][c];
          }
        }
      }
    }
    for (int r = 0; r < kNodes; ++r)
    {
      std::copy(m[r] + kNodes, m[r] + 2 * kNodes, inverse[r]);
    }
  }

  /// The matrix taking a Lagrange cell's nodal values (VTK order) to its Bernstein coefficients
  /// (VTK order): the inverse of B_b(alpha_a / P), computed once.
  struct Conversion
  {
    double m[kNodes][kNodes];
  };

  static const Conversion& lagrangeToBezier()
  {
    // B is well conditioned (condition numbers 2.9, 6.7, 15 for P = 2, 3, 4): Gauss-Jordan with
    // partial pivoting inverts it to rounding.
    static const Conversion conversion = [] {
      Conversion basisAtNodes, inverse;
      for (int row = 0; row < kNodes; ++row)
      {
        double L[4];
        nodePoint(row, L);
        for (int col = 0; col < kNodes; ++col)
        {
          basisAtNodes.m[row][col] = basisAt(kLatticeOfNode[col], L);
        }
      }
      invert(basisAtNodes.m, inverse.m);
      return inverse;
    }();
    return conversion;
  }

  /// A Lagrange cell's nodal values (VTK order) to Bernstein coefficients (VTK order), in place.
  /// T is double or a 3-vector.
  template <typename T>
  static void toBezier(T* values)
  {
    const Conversion& c = lagrangeToBezier();
    T converted[kNodes];
    for (int r = 0; r < kNodes; ++r)
    {
      T sum = c.m[r][0] * values[0];
      for (int k = 1; k < kNodes; ++k)
      {
        sum += c.m[r][k] * values[k];
      }
      converted[r] = sum;
    }
    std::copy(converted, converted + kNodes, values);
  }
};

/// The barycentric point of VTK node n of a tetrahedron of order 1..kMaxTetOrder (for order 2,
/// VTK_QUADRATIC_TETRA's node order too: its edge (0,2) is the Lagrange cell's (2,0)).
inline void tetNodePoint(int order, int n, double L[4])
{
  switch (order)
  {
    case 1:
      HigherOrderTet<1>::nodePoint(n, L);
      return;
    case 2:
      HigherOrderTet<2>::nodePoint(n, L);
      return;
    default:
      forHigherOrder(order, [&](auto P) { HigherOrderTet<decltype(P)::value>::nodePoint(n, L); });
  }
}

} // namespace tetdsr
