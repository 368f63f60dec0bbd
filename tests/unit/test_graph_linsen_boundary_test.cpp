// linsen_boundary_test: edge (boundary of a smooth surface) or intersection ([IvoMSc] §4.1).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/linsen_boundary_test.h"

namespace splatkit::graph {
namespace {

constexpr double kPi = std::numbers::pi;

// Points at the given angles (degrees) on a circle of radius 1 in the plane z = 0, with a height
// offset that the projection must ignore.
std::vector<Vec3f> ring(std::initializer_list<double> degrees) {
  std::vector<Vec3f> out;
  float h = 0.1f;
  for (double d : degrees) {
    const double a = d * kPi / 180;
    out.push_back({float(std::cos(a)), float(std::sin(a)), h});
    h = -h;
  }
  return out;
}

TEST(GraphLinsenBoundaryTest, FullRingIsInsideASurface) {
  const auto r = linsen_boundary_test({0, 0, 0}, {0, 0, 1},
                                      ring({0, 45, 90, 135, 180, 225, 270, 315}), kPi / 2);
  EXPECT_FALSE(r.boundary);
  EXPECT_EQ(r.directions, 8);
  EXPECT_NEAR(r.max_gap, kPi / 4, 1e-6);
}

TEST(GraphLinsenBoundaryTest, HalfRingIsAnEdge) {
  const auto r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, ring({0, 45, 90, 135, 180}), kPi / 2);
  EXPECT_TRUE(r.boundary);
  EXPECT_NEAR(r.max_gap, kPi, 1e-6);
}

TEST(GraphLinsenBoundaryTest, GapAcrossTheAngleSeam) {
  // Clustered around 180°, where atan2 jumps from +π to -π: one gap of 340°.
  auto r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, ring({170, 180, 190}), kPi / 2);
  EXPECT_TRUE(r.boundary);
  EXPECT_NEAR(r.max_gap, 340 * kPi / 180, 1e-6);
  // A full ring turned by 3° so that neighbours sit on both sides of the seam.
  r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, ring({3, 48, 93, 138, 183, 228, 273, 318}),
                           kPi / 2);
  EXPECT_FALSE(r.boundary);
  EXPECT_NEAR(r.max_gap, kPi / 4, 1e-6);
}

TEST(GraphLinsenBoundaryTest, ThresholdDecides) {
  const auto nbrs = ring({0, 60, 120, 180, 240});  // largest gap 120° (240° -> 360°)
  EXPECT_TRUE(linsen_boundary_test({0, 0, 0}, {0, 0, 1}, nbrs, 100 * kPi / 180).boundary);
  EXPECT_FALSE(linsen_boundary_test({0, 0, 0}, {0, 0, 1}, nbrs, 130 * kPi / 180).boundary);
}

TEST(GraphLinsenBoundaryTest, TiltedFrameGivesSameGaps) {
  // The half ring, rotated so that the splat's normal is (0, -0.6, 0.8) and moved to (1, 2, 3).
  const Vec3f c{1, 2, 3}, n{0, -0.6f, 0.8f}, e1{1, 0, 0}, e2 = cross(n, e1);
  std::vector<Vec3f> nbrs;
  for (const Vec3f& p : ring({0, 45, 90, 135, 180}))
    nbrs.push_back(c + e1 * p.x + e2 * p.y + n * p.z);
  const auto r = linsen_boundary_test(c, n, nbrs, kPi / 2);
  EXPECT_TRUE(r.boundary);
  EXPECT_NEAR(r.max_gap, kPi, 1e-5);
  // And the bottom-facing normal (Duff's frame takes its other branch).
  const auto flipped = linsen_boundary_test(c, -n, nbrs, kPi / 2);
  EXPECT_NEAR(flipped.max_gap, kPi, 1e-5);
}

TEST(GraphLinsenBoundaryTest, FewerThanTwoDirectionsIsAnEdge) {
  auto r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, {}, 2 * kPi);
  EXPECT_TRUE(r.boundary);
  EXPECT_EQ(r.directions, 0);
  EXPECT_EQ(r.max_gap, 2 * kPi);
  r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, ring({30}), 2 * kPi);
  EXPECT_TRUE(r.boundary);
  EXPECT_EQ(r.directions, 1);
  // A neighbour straight above the centre and one at the centre give no direction.
  const std::vector<Vec3f> above{{0, 0, 0.5f}, {0, 0, 0}, {1, 0, 0}};
  r = linsen_boundary_test({0, 0, 0}, {0, 0, 1}, above, kPi / 2);
  EXPECT_TRUE(r.boundary);
  EXPECT_EQ(r.directions, 1);
}

}  // namespace
}  // namespace splatkit::graph
