// cover_splat: the splat that covers a point's tangent-plane Voronoi cell, on configurations with
// exact answers.
#include "normals/cover_splat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace splatkit {
namespace {

struct Config {
  std::vector<Vec3f> positions{{0, 0, 0}};  // the centre first
  std::vector<uint32_t> row{0};
  void add(Vec3f p) {
    row.push_back(static_cast<uint32_t>(positions.size()));
    positions.push_back(p);
  }
  SplatShape fit(float cap, bool ellipse, Vec3f normal = {0, 0, 1}) const {
    return cover_splat(positions[0], normal, positions, row, cap, ellipse);
  }
};

TEST(NormalsCoverSplat, HexagonalNeighboursGiveTheHexagonsCircumradius) {
  Config c;
  for (int k = 0; k < 6; ++k) {
    const float a = static_cast<float>(k) * std::numbers::pi_v<float> / 3;
    c.add({std::cos(a), std::sin(a), 0});
  }
  const SplatShape s = c.fit(10, false);
  EXPECT_NEAR(s.radius, 1 / std::sqrt(3.0f), 1e-6);  // the cell's vertices
  EXPECT_FALSE(s.open);
  const SplatShape e = c.fit(10, true);  // a round cell: the circle is the smallest
  EXPECT_NEAR(e.radius, s.radius, 1e-6);
  EXPECT_NEAR(e.minor_radius, s.radius, 1e-6);
}

TEST(NormalsCoverSplat, ScanLinesGiveAnEllipseAcrossTheLines) {
  // Lines y = ±2, points every 0.5 along x: the cell is [-0.25, 0.25] × [-1, 1].
  Config c;
  for (float y : {-2.0f, 0.0f, 2.0f})
    for (int i = -4; i <= 4; ++i)
      if (y != 0 || i != 0) c.add({0.5f * static_cast<float>(i), y, 0});
  const SplatShape circle = c.fit(10, false);
  EXPECT_NEAR(circle.radius, std::hypot(0.25f, 1.0f), 1e-5);
  const SplatShape e = c.fit(10, true);
  EXPECT_FALSE(e.open);
  EXPECT_NEAR(std::fabs(e.axis.y), 1.0f, 1e-5);         // the long axis runs across the lines
  EXPECT_NEAR(e.minor_radius / e.radius, 0.25f, 1e-4);  // the rectangle's aspect
  // Every corner of the cell is inside: (0.25 / b)² + (1 / a)² <= 1, with equality.
  EXPECT_NEAR(std::pow(0.25f / e.minor_radius, 2) + std::pow(1.0f / e.radius, 2), 1.0f, 1e-4);
  EXPECT_LT(e.radius * e.minor_radius, 0.55f * circle.radius * circle.radius);
}

TEST(NormalsCoverSplat, OneSidedNeighboursLeaveAnOpenCellCutAtTheCap) {
  Config c;
  c.add({1, 0, 0});
  c.add({1, 1, 0});
  c.add({1, -1, 0});
  const SplatShape s = c.fit(0.8f, false);
  EXPECT_TRUE(s.open);
  EXPECT_FLOAT_EQ(s.radius, 0.8f);
}

TEST(NormalsCoverSplat, NeighboursOfAnotherSheetAndDuplicatesAreSkipped) {
  // Neighbours on three sides: the cell is open towards +x.
  Config c;
  c.add({-1, 0, 0});
  c.add({0, 1, 0});
  c.add({0, -1, 0});
  c.add({0, 0, 0});        // a duplicate of the centre: no bisector
  c.add({0.2f, 0, 1.0f});  // 79° above the plane (across a crease): would close the cell at x = 0.1
  const SplatShape s = c.fit(5, false);
  EXPECT_TRUE(s.open);
  // A border open to one side: cut open_cap / 4 past the centre, across that side (the strip
  // [-0.5, 1.25] x [-0.5, 0.5]), not at the cap.
  EXPECT_NEAR(s.radius, std::hypot(1.25f, 0.5f), 1e-5);
  Config flat = c;
  flat.positions.back() = {0.2f, 0, 0.1f};  // 27°: the same sheet, it closes the cell
  const SplatShape t = flat.fit(5, false);
  EXPECT_FALSE(t.open);
  EXPECT_NEAR(t.radius, std::hypot(0.5f, 0.5f), 1e-5);  // the corners (-0.5, ±0.5)
}

TEST(NormalsCoverSplat, TangentAxisIsAUnitPerpendicular) {
  for (Vec3f n : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, normalized(Vec3f{1, 2, 3}),
                  normalized(Vec3f{-0.3f, 0.1f, -0.9f})}) {
    const Vec3f t = tangent_axis(n);
    EXPECT_NEAR(norm(t), 1.0f, 1e-6);
    EXPECT_NEAR(dot(t, n), 0.0f, 1e-6);
  }
}

}  // namespace
}  // namespace splatkit
