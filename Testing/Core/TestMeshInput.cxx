// The mesh contract (MeshInput.h): arrays in VTK's layouts and number types give the same scene
// as the core's own (float64 points and field, int64 ids), bit for bit; every size the arrays
// claim is checked before anything is read; every skipped cell is counted and told.
#include "LatticeMesh.h"

#include "tetdsr/common/CellTypes.h"
#include "tetdsr/input/MeshInput.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using tetdsr_test::LatticeMesh;
using tetdsr_test::makeLattice;

namespace
{
/// The arrays of a lattice in the core's own layout (every one viewed, none copied).
struct LatticeArrays
{
  explicit LatticeArrays(const LatticeMesh& mesh)
    : Mesh(mesh)
  {
    const tetdsr::MeshView view = Mesh.view();
    Types.assign(view.cellTypes, view.cellTypes + view.numberOfCells);
    Offsets.assign(view.offsets, view.offsets + view.numberOfCells + 1);
  }

  tetdsr::MeshArrays arrays() const
  {
    tetdsr::MeshArrays a;
    a.points = { Mesh.points.data(), tetdsr::NumberType::Float64,
      static_cast<tetdsr::NodeId>(Mesh.points.size() / 3), 3, "points" };
    a.cellTypes = { Types.data(), tetdsr::NumberType::UInt8,
      static_cast<tetdsr::NodeId>(Types.size()), 1, "types" };
    a.offsets = { Offsets.data(), tetdsr::NumberType::Int64,
      static_cast<tetdsr::NodeId>(Offsets.size()), 1, "offsets" };
    a.connectivity = { Mesh.cellNodes.data(), tetdsr::NumberType::Int64,
      static_cast<tetdsr::NodeId>(Mesh.cellNodes.size()), 1, "connectivity" };
    a.field = { Mesh.values.data(), tetdsr::NumberType::Float64,
      static_cast<tetdsr::NodeId>(Mesh.values.size()), 1, "f" };
    return a;
  }

  LatticeMesh Mesh;
  std::vector<std::uint8_t> Types;
  std::vector<tetdsr::NodeId> Offsets;
};

/// The first hits of a fan of rays through the lattice [0, 1]^3, for a bit-for-bit comparison.
std::vector<tetdsr::SurfaceHit> castFan(tetdsr::PreparedMesh& prepared, double iso)
{
  const tetdsr::SurfaceIndex& surface = prepared.surface({ iso }, tetdsr::serialFor);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.1, 1.7, 2.9);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, 24, 24);
  std::vector<tetdsr::SurfaceHit> hits;
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 24; ++i)
    {
      tetdsr::SurfaceHit hit;
      hit.t = surface.firstHit(rays.pixelRay(i, j), hit) ? hit.t : -1.0;
      hits.push_back(hit);
    }
  return hits;
}

void expectSameHits(const std::vector<tetdsr::SurfaceHit>& a, const std::vector<tetdsr::SurfaceHit>& b)
{
  ASSERT_EQ(a.size(), b.size());
  int hits = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    EXPECT_EQ(a[k].t, b[k].t) << "ray " << k;
    EXPECT_EQ(a[k].cellId, b[k].cellId) << "ray " << k;
    EXPECT_EQ(a[k].gradient, b[k].gradient) << "ray " << k;
    hits += a[k].t >= 0.0;
  }
  EXPECT_GT(hits, 40) << "the fan must meet the surface (a sphere of radius 0.32 in view)";
}

LatticeMesh sphereLattice()
{
  LatticeMesh mesh = makeLattice(3, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return glm::dot(x - 0.5, x - 0.5); });
  return mesh;
}
} // namespace

TEST(MeshInput, OtherNumberTypesGiveTheSameSceneBitForBit)
{
  const LatticeArrays own(sphereLattice());
  tetdsr::Messages messages;
  tetdsr::PreparedMesh reference;
  ASSERT_TRUE(reference.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  EXPECT_TRUE(messages.errors.empty() && messages.warnings.empty());
  EXPECT_EQ(reference.memoryBytes(), reference.scene()->memoryBytes() +
      reference.surface({ 0.1 }, tetdsr::serialFor).memoryBytes())
    << "float64 points and field, int64 ids: viewed, not copied";

  // 32-bit ids, the field as the second component of a float64 pair, and as int32 values of a
  // field that is integer-valued (the field times 1000, rounded; iso-value scaled alike).
  std::vector<std::int32_t> offsets32(own.Offsets.begin(), own.Offsets.end());
  std::vector<std::int32_t> ids32(own.Mesh.cellNodes.begin(), own.Mesh.cellNodes.end());
  std::vector<double> pairs;
  for (double v : own.Mesh.values)
  {
    pairs.push_back(-1.0);
    pairs.push_back(v);
  }
  tetdsr::MeshArrays other = own.arrays();
  other.offsets = { offsets32.data(), tetdsr::NumberType::Int32, other.offsets.tuples, 1, "" };
  other.connectivity = { ids32.data(), tetdsr::NumberType::Int32, other.connectivity.tuples, 1, "" };
  other.field = { pairs.data(), tetdsr::NumberType::Float64, other.field.tuples, 2, "pair" };
  other.fieldComponent = 1;
  tetdsr::PreparedMesh converted;
  ASSERT_TRUE(converted.prepare(other, tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  EXPECT_GT(converted.memoryBytes(), converted.scene()->memoryBytes() +
      converted.surface({ 0.1 }, tetdsr::serialFor).memoryBytes())
    << "converted copies are counted";
  expectSameHits(castFan(reference, 0.1), castFan(converted, 0.1));

  LatticeMesh integers = own.Mesh;
  std::vector<std::int32_t> scaled;
  for (double& v : integers.values)
  {
    v = std::round(1000.0 * v);
    scaled.push_back(static_cast<std::int32_t>(v));
  }
  const LatticeArrays integerOwn(integers);
  tetdsr::MeshArrays integerArrays = integerOwn.arrays();
  integerArrays.field = { scaled.data(), tetdsr::NumberType::Int32, integerArrays.field.tuples, 1, "" };
  tetdsr::PreparedMesh a, b;
  ASSERT_TRUE(a.prepare(integerOwn.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  ASSERT_TRUE(b.prepare(integerArrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  expectSameHits(castFan(a, 100.0), castFan(b, 100.0));
}

TEST(MeshInput, FloatPointsRoundAtSinglePrecision)
{
  // A mid-edge node off its edge's midpoint by 1e-9 of the cell: curved in double, rounding in
  // float (2^-23 relative, 64 times that is 7.6e-6).
  LatticeMesh mesh = makeLattice(1, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return x.x; });
  mesh.setPoint(mesh.cellNodes[4], mesh.point(mesh.cellNodes[4]) + glm::dvec3(0.0, 1e-9, 0.0));
  const LatticeArrays own(mesh);
  tetdsr::Messages messages;
  tetdsr::PreparedMesh asDouble;
  ASSERT_TRUE(asDouble.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  EXPECT_GE(asDouble.summary().curvedCells, 1);
  std::vector<float> floats(mesh.points.begin(), mesh.points.end());
  tetdsr::MeshArrays arrays = own.arrays();
  arrays.points = { floats.data(), tetdsr::NumberType::Float32, arrays.points.tuples, 3, "" };
  tetdsr::PreparedMesh asFloat;
  ASSERT_TRUE(asFloat.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  EXPECT_EQ(asFloat.summary().curvedCells, 0);
  EXPECT_EQ(asFloat.summary().validCells, asDouble.summary().validCells);
}

TEST(MeshInput, SizesTheArraysClaimAreCheckedBeforeReading)
{
  const LatticeArrays own(sphereLattice());
  const tetdsr::NodeId points = own.arrays().points.tuples;
  const tetdsr::NodeId cells = own.arrays().offsets.tuples - 1;
  struct Case
  {
    const char* what;
    void (*spoil)(tetdsr::MeshArrays&);
    std::string expected;
  };
  const std::vector<Case> cases = {
    { "no points", [](tetdsr::MeshArrays& a) { a.points.tuples = 0; },
      "The input mesh is empty: it has no cells or no points." },
    { "no offsets", [](tetdsr::MeshArrays& a) { a.offsets.tuples = 0; },
      "The input mesh is empty: it has no cells or no points." },
    { "short types", [](tetdsr::MeshArrays& a) { a.cellTypes.tuples -= 1; },
      "The input's cell types array has " + std::to_string(cells - 1) + " values for " +
        std::to_string(cells) + " cells." },
    { "types not bytes", [](tetdsr::MeshArrays& a) { a.cellTypes.type = tetdsr::NumberType::Int32; },
      "The input's cell types array has " + std::to_string(cells) + " values for " +
        std::to_string(cells) + " cells." },
    { "float offsets", [](tetdsr::MeshArrays& a) { a.offsets.type = tetdsr::NumberType::Float64; },
      "The input's cell offsets and connectivity must be arrays of 32- or 64-bit integers with one "
      "component." },
    { "2-d points", [](tetdsr::MeshArrays& a) { a.points.components = 2; },
      "The input's points have 2 components: points need 3 (x, y, z)." },
    { "short field", [](tetdsr::MeshArrays& a) { a.field.tuples -= 1; },
      "Point array 'f' has " + std::to_string(points - 1) + " tuples for " +
        std::to_string(points) + " points." },
    { "component", [](tetdsr::MeshArrays& a) { a.fieldComponent = 1; },
      "Component 1 of point array 'f' is out of range: it has 1 components." },
  };
  for (const Case& c : cases)
  {
    tetdsr::MeshArrays arrays = own.arrays();
    c.spoil(arrays);
    tetdsr::Messages messages;
    tetdsr::PreparedMesh prepared;
    EXPECT_FALSE(prepared.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages))
      << c.what;
    ASSERT_EQ(messages.errors.size(), 1u) << c.what;
    EXPECT_EQ(messages.errors[0], c.expected) << c.what;
    EXPECT_EQ(prepared.scene(), nullptr) << c.what;
    tetdsr::Messages again;
    EXPECT_FALSE(prepared.reuse(again)) << c.what;
    EXPECT_EQ(again.errors, messages.errors) << c.what << ": told again on reuse";
  }
}

TEST(MeshInput, CellsOfOtherTypesAndMalformedCellsAreCountedAndTold)
{
  LatticeArrays own(sphereLattice());
  // Cell 0 an unsupported type (a pentagonal prism, 15: hexahedra, 12, are read now); cell 1
  // claiming VTK_TETRA with 10 ids; cell 2 an offset past the end (its ids would be read beyond
  // the array).
  own.Types[0] = 15;
  own.Types[1] = tetdsr::kVtkTetra;
  tetdsr::MeshArrays arrays = own.arrays();
  std::vector<tetdsr::NodeId> offsets = own.Offsets;
  offsets[3] = std::numeric_limits<tetdsr::NodeId>::max() / 2;
  arrays.offsets.data = offsets.data();
  tetdsr::Messages messages;
  tetdsr::PreparedMesh prepared;
  ASSERT_TRUE(prepared.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  const tetdsr::PreprocessSummary& summary = prepared.summary();
  EXPECT_EQ(summary.unsupportedCells, 1);
  EXPECT_EQ(summary.malformedCells, 3) << "cell 1 (10 ids for 4), cells 2 and 3 (offset 3)";
  EXPECT_EQ(summary.validCells, arrays.offsets.tuples - 1 - 4);
  ASSERT_EQ(messages.warnings.size(), 2u);
  const std::string reads = "VTK_TETRA, VTK_QUADRATIC_TETRA, VTK_LAGRANGE_TETRAHEDRON or "
    "VTK_BEZIER_TETRAHEDRON of order 1 to 4; VTK_HEXAHEDRON, VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON, "
    "VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON or "
    "VTK_BEZIER_HEXAHEDRON of order 1 to 4; VTK_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE, "
    "VTK_QUADRATIC_WEDGE, VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE or "
    "VTK_BEZIER_WEDGE of order 1 to 4; VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID";
  EXPECT_EQ(messages.warnings[0], "Skipped 1 cells of a type TetDSR does not read (it reads " + reads +
      "; not VTK_LAGRANGE_PYRAMID or VTK_BEZIER_PYRAMID: VTK 9.2 has no cell class of the type).");
  EXPECT_EQ(messages.warnings[1].rfind("Skipped 3 malformed cells: a number of node ids", 0), 0u)
    << messages.warnings[1];
  // The node counts of every kind read, from the cell type table (TestCellTypes checks that text).
  EXPECT_NE(messages.warnings[1].find("(" + tetdsr::nodeCountsText() + ";"), std::string::npos)
    << messages.warnings[1];

  // Every cell of another type: nothing can be rendered, and the error says why.
  std::fill(own.Types.begin(), own.Types.end(), std::uint8_t(15));
  tetdsr::Messages none;
  tetdsr::PreparedMesh nothing;
  EXPECT_FALSE(nothing.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, none));
  ASSERT_EQ(none.errors.size(), 1u);
  EXPECT_EQ(none.errors[0], "No cell can be rendered: none of the " +
      std::to_string(own.Types.size()) + " input cells is a well-formed cell of a type TetDSR "
      "reads (" + reads + "): " + std::to_string(own.Types.size()) +
      " of another type, 0 of an order it does not read, 0 malformed.");
  EXPECT_TRUE(none.warnings.empty());
}

TEST(MeshInput, ColourValuesAreViewedOrConvertedAndCheckedForLength)
{
  const LatticeArrays own(sphereLattice());
  tetdsr::Messages messages;
  tetdsr::PreparedMesh prepared;
  ASSERT_TRUE(prepared.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  const tetdsr::NodeId points = own.arrays().points.tuples;
  std::vector<float> colours(static_cast<std::size_t>(2 * points));
  for (std::size_t k = 0; k < colours.size(); ++k)
  {
    colours[k] = static_cast<float>(k) * 0.5f;
  }
  const tetdsr::ArrayView view{ colours.data(), tetdsr::NumberType::Float32, points, 2, "c" };
  const double* values = prepared.pointValues(view, 1, "colour array", messages);
  ASSERT_NE(values, nullptr);
  for (std::size_t k = 0; k < colours.size(); ++k)
  {
    ASSERT_EQ(values[k], static_cast<double>(colours[k])) << "value " << k;
  }
  EXPECT_EQ(prepared.pointValues(view, 1, "colour array", messages), values) << "kept";
  const tetdsr::ArrayView doubles{ own.Mesh.values.data(), tetdsr::NumberType::Float64, points, 1, "" };
  EXPECT_EQ(prepared.pointValues(doubles, 2, "colour array", messages), own.Mesh.values.data())
    << "float64: viewed";
  const tetdsr::ArrayView shortView{ colours.data(), tetdsr::NumberType::Float32, points - 1, 2, "c" };
  EXPECT_EQ(prepared.pointValues(shortView, 3, "colour array", messages), nullptr);
  ASSERT_EQ(messages.errors.size(), 1u);
  EXPECT_EQ(messages.errors[0], "The colour array 'c' has " + std::to_string(points - 1) +
      " tuples for " + std::to_string(points) + " points.");
}

TEST(MeshInput, AKeptSceneSurvivesEditsOfTheArraysItViews)
{
  // VTK's contract is that an edited array is marked Modified(), and then the face rebuilds the
  // scene; an edit in place without it (numpy makes that easy) must give a stale or missing
  // cell, never a read outside the arrays. Every cell is made curved (a mid-edge node moved) in
  // half the lattice, so that the curved path, which reads the mesh for every ray, is covered.
  LatticeMesh mesh = sphereLattice();
  for (std::size_t c = 0; c < mesh.cellNodes.size() / 10; c += 2)
  {
    const tetdsr::NodeId id = mesh.cellNodes[10 * c + 4];
    mesh.setPoint(id, mesh.point(id) + glm::dvec3(0.0, 0.0, 1e-3));
  }
  LatticeArrays own(mesh);
  tetdsr::Messages messages;
  tetdsr::PreparedMesh prepared;
  ASSERT_TRUE(prepared.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  ASSERT_GT(prepared.summary().curvedCells, 0);
  tetdsr::Scene& scene = *prepared.scene();
  const std::vector<tetdsr::SurfaceHit> before = castFan(prepared, 0.1);

  // Edits: ids beyond the points and negative, a cell re-typed to need more ids than it has, an
  // offset past the end of the connectivity.
  const auto cells = static_cast<tetdsr::NodeId>(own.Types.size());
  for (tetdsr::NodeId c = 0; c < cells; c += 3)
  {
    own.Mesh.cellNodes[10 * c + 5] = 1000000000000LL;
  }
  own.Mesh.cellNodes[10 * 1 + 2] = -7;
  own.Types[4] = tetdsr::kVtkTetra;
  own.Offsets[cells] = own.Offsets[cells] + 1000;
  // The arrays the scene views are these (LatticeArrays keeps them): nothing was copied.
  scene.computeNodalGradients();
  const std::vector<tetdsr::SurfaceHit> after = castFan(prepared, 0.2); // a new surface index
  int hits = 0;
  for (const tetdsr::SurfaceHit& hit : after)
  {
    if (hit.t >= 0.0)
    {
      ++hits;
      EXPECT_NE(hit.cellId % 3, 0) << "an edited cell was hit";
      EXPECT_TRUE(std::isfinite(scene.interpolate(hit.cellId, glm::dvec3(0.5), own.Mesh.values.data())) ||
        hit.cellId == 1 || hit.cellId == 4 || hit.cellId == cells - 1);
      (void)scene.interpolateNodalGradient(hit.cellId, glm::dvec3(0.5));
    }
  }
  EXPECT_GT(hits, 0) << "the cells not edited still render";
  for (tetdsr::NodeId c = 0; c < cells; c += 3)
  {
    EXPECT_TRUE(std::isnan(scene.interpolate(c, glm::dvec3(0.5), own.Mesh.values.data())))
      << "cell " << c << ": its ids were edited out of range";
  }
  tetdsr::NodeId found = -1;
  (void)scene.locate(glm::dvec3(0.5), found);
  EXPECT_EQ(before.size(), after.size());
}

TEST(IsoValues, ManyInOneCellGiveTheFirstCrossingOfAny)
{
  // 300 iso-values over the range of a field with a minimum inside the lattice (so rays see the
  // field fall, then rise): each ray's first hit must be the nearest of the 300 single-value
  // hits, found by search instead of 300 solves per cell (the cost grows with their logarithm).
  LatticeMesh mesh = makeLattice(3, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) {
    return glm::dot(x - glm::dvec3(0.4, 0.55, 0.5), x - glm::dvec3(0.4, 0.55, 0.5)) + 0.3 * x.x;
  });
  const LatticeArrays own(mesh);
  tetdsr::Messages messages;
  tetdsr::PreparedMesh prepared;
  ASSERT_TRUE(prepared.prepare(own.arrays(), tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  std::vector<double> values;
  for (int k = 0; k < 300; ++k)
  {
    values.push_back(0.05 + 0.7 * k / 299.0);
  }
  const tetdsr::SurfaceIndex many(*prepared.scene(), tetdsr::IsoValues(values));
  std::vector<std::unique_ptr<tetdsr::SurfaceIndex>> single;
  for (double v : values)
  {
    single.push_back(std::make_unique<tetdsr::SurfaceIndex>(*prepared.scene(), tetdsr::IsoValues({ v })));
  }
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.1, 1.7, 2.9);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, 20, 20);
  int hits = 0;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      double nearest = std::numeric_limits<double>::infinity();
      std::size_t nearestValue = 0;
      for (std::size_t k = 0; k < single.size(); ++k)
      {
        tetdsr::SurfaceHit hit;
        if (single[k]->firstHit(ray, hit) && hit.t < nearest)
        {
          nearest = hit.t;
          nearestValue = k;
        }
      }
      tetdsr::SurfaceHit hit;
      const bool found = many.firstHit(ray, hit);
      ASSERT_EQ(found, std::isfinite(nearest)) << "pixel " << i << ", " << j;
      if (found)
      {
        ++hits;
        EXPECT_EQ(hit.t, nearest) << "pixel " << i << ", " << j << ": expected the hit of value "
                                  << nearestValue << ", got value " << hit.isoIndex;
      }
    }
  EXPECT_GT(hits, 200);
}

TEST(MeshInput, AnEmptyRationalWeightsArrayIsAShortOneNotNone)
{
  // (Found by the fuzzer: an empty array's data pointer is null, as "no array" was told apart.)
  LatticeArrays own(makeLattice(1, glm::dvec3(0.0), 1.0));
  own.Mesh.sample([](const glm::dvec3& x) { return x.x; });
  for (const bool given : { false, true })
  {
    tetdsr::MeshArrays arrays = own.arrays();
    arrays.rationalWeights = { nullptr, tetdsr::NumberType::Float64, 0, 1, "RationalWeights" };
    arrays.hasRationalWeights = given;
    tetdsr::Messages messages;
    tetdsr::PreparedMesh prepared;
    EXPECT_EQ(prepared.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages), !given);
    if (given)
    {
      ASSERT_EQ(messages.errors.size(), 1u);
      EXPECT_EQ(messages.errors[0], "The rational weights array 'RationalWeights' has 0 tuples of 1 "
        "components for " + std::to_string(arrays.points.tuples) + " points: it needs one value per point.");
    }
  }
}

// Ghost cells (VTK's vtkGhostType cell array): a cell flagged duplicate or hidden is left out
// (the piece that owns it draws it), counted, and never named by a hit; the other flags' cells
// are drawn. The scene left is the one without those cells, hit for hit.
TEST(MeshInput, GhostCellsAreLeftOutCountedAndNeverHit)
{
  const LatticeArrays own(sphereLattice());
  const std::size_t cells = own.Types.size();
  std::vector<std::uint8_t> ghosts(cells, 0);
  std::vector<std::uint8_t> withoutGhostCells = own.Types; // left out as unsupported instead
  tetdsr::NodeId expected = 0;
  for (std::size_t c = 0; c < cells; ++c)
  {
    // Duplicates, hidden cells, and cells with only the flags that describe drawn cells
    // (high/low connectivity, refined, exterior), some with the duplicate bit among others.
    const std::uint8_t kinds[] = { 1, 0, 32, 16, 4 | 1, 2, 8, 0, 16 | 32 };
    ghosts[c] = kinds[c % (sizeof kinds)];
    if (ghosts[c] & (tetdsr::kGhostDuplicateCell | tetdsr::kGhostHiddenCell))
    {
      ++expected;
      withoutGhostCells[c] = 0; // VTK_EMPTY_CELL
    }
  }
  ASSERT_GT(expected, 0);
  tetdsr::MeshArrays arrays = own.arrays();
  arrays.cellGhosts = { ghosts.data(), tetdsr::NumberType::UInt8,
    static_cast<tetdsr::NodeId>(cells), 1, "vtkGhostType" };
  arrays.hasCellGhosts = true;
  tetdsr::Messages messages;
  tetdsr::PreparedMesh prepared;
  ASSERT_TRUE(prepared.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages));
  EXPECT_TRUE(messages.errors.empty());
  EXPECT_TRUE(messages.warnings.empty()) << "ghost cells are expected in a piece: no warning";
  EXPECT_EQ(prepared.summary().ghostCells, expected);
  EXPECT_EQ(prepared.summary().validCells, static_cast<tetdsr::NodeId>(cells) - expected);

  tetdsr::MeshArrays reference = own.arrays();
  reference.cellTypes.data = withoutGhostCells.data();
  tetdsr::Messages referenceMessages;
  tetdsr::PreparedMesh without;
  ASSERT_TRUE(
    without.prepare(reference, tetdsr::TransverseTest(), tetdsr::serialFor, referenceMessages));
  EXPECT_EQ(without.summary().unsupportedCells, expected);
  const std::vector<tetdsr::SurfaceHit> hits = castFan(prepared, 0.1);
  expectSameHits(hits, castFan(without, 0.1));
  for (const tetdsr::SurfaceHit& hit : hits)
  {
    if (hit.t >= 0.0)
    {
      EXPECT_EQ(ghosts[hit.cellId] & (tetdsr::kGhostDuplicateCell | tetdsr::kGhostHiddenCell), 0)
        << "a hit names ghost cell " << hit.cellId;
    }
  }
}

TEST(MeshInput, GhostArraysAreCheckedAndAllGhostPiecesSaySo)
{
  const LatticeArrays own(sphereLattice());
  const auto cells = static_cast<tetdsr::NodeId>(own.Types.size());
  std::vector<std::uint8_t> ghosts(own.Types.size(), 1);
  std::vector<std::int32_t> wide(own.Types.size(), 0);
  auto prepare = [&](const tetdsr::ArrayView& view, tetdsr::Messages& messages) {
    tetdsr::MeshArrays arrays = own.arrays();
    arrays.cellGhosts = view;
    arrays.hasCellGhosts = true;
    tetdsr::PreparedMesh prepared;
    return prepared.prepare(arrays, tetdsr::TransverseTest(), tetdsr::serialFor, messages);
  };
  {
    tetdsr::Messages messages; // one value short
    EXPECT_FALSE(prepare({ ghosts.data(), tetdsr::NumberType::UInt8, cells - 1, 1, "vtkGhostType" },
      messages));
    ASSERT_EQ(messages.errors.size(), 1u);
    EXPECT_NE(messages.errors[0].find("cell ghost array 'vtkGhostType' has " +
                std::to_string(cells - 1) + " tuples"),
      std::string::npos)
      << messages.errors[0];
  }
  {
    tetdsr::Messages messages; // 32-bit integers
    EXPECT_FALSE(
      prepare({ wide.data(), tetdsr::NumberType::Int32, cells, 1, "vtkGhostType" }, messages));
    ASSERT_EQ(messages.errors.size(), 1u);
    EXPECT_NE(messages.errors[0].find("other than unsigned 8-bit"), std::string::npos)
      << messages.errors[0];
  }
  {
    tetdsr::Messages messages; // a null pointer that claims values
    EXPECT_FALSE(prepare({ nullptr, tetdsr::NumberType::UInt8, cells, 1, "vtkGhostType" }, messages));
    EXPECT_EQ(messages.errors.size(), 1u);
  }
  {
    tetdsr::Messages messages; // every cell a ghost
    EXPECT_FALSE(
      prepare({ ghosts.data(), tetdsr::NumberType::UInt8, cells, 1, "vtkGhostType" }, messages));
    ASSERT_EQ(messages.errors.size(), 1u);
    EXPECT_NE(messages.errors[0].find(std::to_string(cells) + " of them ghost cells"),
      std::string::npos)
      << messages.errors[0];
  }
}

TEST(MeshInput, InputKindsAndBlocksAreChecked)
{
  tetdsr::Messages messages;
  EXPECT_TRUE(tetdsr::checkInputKind(true, "vtkUnstructuredGrid", messages));
  EXPECT_FALSE(tetdsr::checkInputKind(false, "vtkPolyData", messages));
  ASSERT_EQ(messages.errors.size(), 1u);
  EXPECT_EQ(messages.errors[0].rfind("A vtkPolyData cannot be drawn", 0), 0u);
  tetdsr::Messages blocks;
  EXPECT_TRUE(tetdsr::checkBlocks(3, 0, blocks));
  EXPECT_TRUE(blocks.warnings.empty() && blocks.errors.empty());
  EXPECT_TRUE(tetdsr::checkBlocks(1, 1, blocks));
  ASSERT_EQ(blocks.warnings.size(), 1u);
  EXPECT_EQ(blocks.warnings[0],
    "1 of 2 blocks of the composite input are not vtkUnstructuredGrid: not drawn.");
  EXPECT_FALSE(tetdsr::checkBlocks(0, 2, blocks));
  EXPECT_EQ(blocks.errors.size(), 1u);
}
