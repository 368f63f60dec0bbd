// disc_disc_intersect: do two splats cross ([IvoMSc] §4.2, fig. 4.2)?
#include <gtest/gtest.h>

#include <cmath>

#include "graph/disc_disc_intersect.h"

namespace splatkit::graph {
namespace {

const SplatDisc kFloor = SplatDisc::circle({0, 0, 0}, {0, 0, 1}, 1);  // unit disc in z = 0

TEST(GraphDiscDiscIntersect, CrossingDiscs) {
  // Wall disc in x = 0.5 centred on the line: chords [-sqrt(0.75), sqrt(0.75)] and [-1, 1].
  const auto r = disc_disc_intersect(kFloor, SplatDisc::circle({0.5f, 0, 0}, {1, 0, 0}, 1));
  ASSERT_EQ(r.status, DiscCrossing::kCross);
  EXPECT_EQ(r.line.direction, (Vec3d{0, 1, 0}));
  EXPECT_EQ(r.line.point, (Vec3d{0.5, 0, 0}));
  EXPECT_DOUBLE_EQ(r.segment_i.t0, -std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(r.segment_i.t1, std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(r.segment_j.t0, -1);
  EXPECT_DOUBLE_EQ(r.segment_j.t1, 1);
  EXPECT_DOUBLE_EQ(r.overlap.t0, -std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(r.overlap.t1, std::sqrt(0.75));
  EXPECT_TRUE(r.crosses());
}

TEST(GraphDiscDiscIntersect, SideBySideIsFalsePositive) {
  // Fig. 4.2a: bounding spheres overlap (|C_i - C_j| = 1.965 < 2) and both discs meet the line,
  // but the chords y in [-0.866, 0.866] and [0.9, 2.9] are disjoint. t counts from P_o, the
  // point of the line nearest the centres' midpoint: y = 0.95 + t.
  const SplatDisc wall = SplatDisc::circle({0.5f, 1.9f, 0}, {1, 0, 0}, 1);
  ASSERT_LT(norm(to_vec3d(wall.center)), 2.0);
  const auto r = disc_disc_intersect(kFloor, wall);
  EXPECT_EQ(r.status, DiscCrossing::kDisjoint);
  EXPECT_FALSE(r.crosses());
  EXPECT_NEAR(r.segment_i.t0, -std::sqrt(0.75) - 0.95, 1e-6);
  EXPECT_NEAR(r.segment_i.t1, std::sqrt(0.75) - 0.95, 1e-6);
  EXPECT_NEAR(r.segment_j.t0, -0.05, 1e-6);
  EXPECT_NEAR(r.segment_j.t1, 1.95, 1e-6);
}

TEST(GraphDiscDiscIntersect, LineMissesOneDisc) {
  EXPECT_EQ(disc_disc_intersect(kFloor, SplatDisc::circle({1.5f, 0, 0}, {1, 0, 0}, 1)).status,
            DiscCrossing::kMissI);
  EXPECT_EQ(disc_disc_intersect(kFloor, SplatDisc::circle({0.5f, 0, 1.5f}, {1, 0, 0}, 1)).status,
            DiscCrossing::kMissJ);
  EXPECT_EQ(disc_disc_intersect(kFloor, SplatDisc::circle({0, 0, 1}, {0, 0, 1}, 1)).status,
            DiscCrossing::kParallel);
}

TEST(GraphDiscDiscIntersect, ChordsTouchingAtOnePointCross) {
  // Line x = 0, z = 0 through P_o = (0, 1, 0): chords [-2, 0] and [0, 2] share t = 0.
  const auto r = disc_disc_intersect(kFloor, SplatDisc::circle({0, 2, 0}, {1, 0, 0}, 1));
  ASSERT_EQ(r.status, DiscCrossing::kCross);
  EXPECT_EQ(r.overlap.t0, 0);
  EXPECT_EQ(r.overlap.t1, 0);
}

TEST(GraphDiscDiscIntersect, EllipseReachesWhereItsBoundingCircleWouldNot) {
  // Wall in x = 1.5. A circle of radius 0.5 misses it; an ellipse with semi-axes 2 (x) and 0.5
  // (y) crosses: u = 0.75, so the chord is y = ±0.5 sqrt(1 - 0.5625).
  const SplatDisc wall = SplatDisc::circle({1.5f, 0, 0}, {1, 0, 0}, 1);
  EXPECT_EQ(disc_disc_intersect(SplatDisc::circle({0, 0, 0}, {0, 0, 1}, 0.5f), wall).status,
            DiscCrossing::kMissI);
  const SplatDisc ellipse = SplatDisc::ellipse({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 2, 0.5f);
  EXPECT_EQ(ellipse.radius, 2);
  const auto r = disc_disc_intersect(ellipse, wall);
  ASSERT_EQ(r.status, DiscCrossing::kCross);
  EXPECT_DOUBLE_EQ(r.overlap.t1, 0.5 * std::sqrt(0.4375));
  EXPECT_DOUBLE_EQ(r.overlap.t0, -0.5 * std::sqrt(0.4375));
}

TEST(GraphDiscDiscIntersect, SwapGivesSameAnswer) {
  const SplatDisc a = SplatDisc::circle({0.1f, 0.2f, 0.3f}, normalized({1, 2, 3}), 0.8f);
  const SplatDisc b = SplatDisc::circle({0.6f, 0.1f, 0.2f}, normalized({-2, 1, 0.5f}), 0.7f);
  const auto ab = disc_disc_intersect(a, b), ba = disc_disc_intersect(b, a);
  ASSERT_EQ(ab.status, DiscCrossing::kCross);
  ASSERT_EQ(ba.status, DiscCrossing::kCross);
  EXPECT_NEAR(ab.overlap.t0, -ba.overlap.t1, 1e-12);
  EXPECT_NEAR(ab.overlap.t1, -ba.overlap.t0, 1e-12);
}

}  // namespace
}  // namespace splatkit::graph
