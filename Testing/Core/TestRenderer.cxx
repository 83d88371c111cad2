// The renderer's colour table: what the VTK adapter samples a lookup table into.
#include "tetdsr/render/Renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

TEST(ColorTable, InterpolatesBetweenSamplesAndClampsOutside)
{
  tetdsr::ColorTable table;
  table.lo = -1.0;
  table.hi = 3.0;
  table.colors = { glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(1.0, 0.0, 0.0) };
  table.nanColor = glm::dvec3(0.25);
  const auto near = [](const glm::dvec3& a, const glm::dvec3& b) {
    return glm::length(a - b) < 1e-15;
  };
  EXPECT_TRUE(near(table.map(-1.0), glm::dvec3(0.0, 0.0, 1.0)));
  EXPECT_TRUE(near(table.map(1.0), glm::dvec3(0.0, 1.0, 0.0))) << "middle sample";
  EXPECT_TRUE(near(table.map(2.0), glm::dvec3(0.5, 0.5, 0.0))) << "halfway between samples";
  EXPECT_TRUE(near(table.map(3.0), glm::dvec3(1.0, 0.0, 0.0)));
  EXPECT_TRUE(near(table.map(-7.0), glm::dvec3(0.0, 0.0, 1.0))) << "clamped below";
  EXPECT_TRUE(near(table.map(1e300), glm::dvec3(1.0, 0.0, 0.0))) << "clamped above";
  EXPECT_TRUE(near(table.map(std::numeric_limits<double>::quiet_NaN()), glm::dvec3(0.25)));
  table.hi = table.lo; // an empty range maps everything to the first colour
  EXPECT_TRUE(near(table.map(5.0), glm::dvec3(0.0, 0.0, 1.0)));
}
