// plane_plane_line: the line of two splat planes ([IvoMSc] eqs. 4.4–4.7).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "graph/plane_plane_line.h"

namespace splatkit::graph {
namespace {

double plane_residual(const Vec3d& p, const Vec3f& c, const Vec3f& n) {
  return dot(p - to_vec3d(c), to_vec3d(n));
}

TEST(GraphPlanePlaneLine, OrthogonalPlanesGiveExactLine) {
  // z = 0 and x = 1 meet in the line x = 1, z = 0; d = (0,0,1) × (1,0,0) = (0,1,0).
  const auto line = plane_plane_line({0, 0, 0}, {0, 0, 1}, {1, 0, 5}, {1, 0, 0});
  ASSERT_TRUE(line.has_value());
  EXPECT_EQ(line->direction, (Vec3d{0, 1, 0}));
  // The point of the line nearest the midpoint of the centres (0.5, 0, 2.5).
  EXPECT_EQ(line->point, (Vec3d{1, 0, 0}));
}

TEST(GraphPlanePlaneLine, ObliquePlanes) {
  // z = 0 and 0.6 x + 0.8 z = 3 meet in x = 5, z = 0.
  const Vec3f ci{0, 0, 0}, ni{0, 0, 1}, cj{5, 0, 0}, nj{0.6f, 0, 0.8f};
  const auto line = plane_plane_line(ci, ni, cj, nj);
  ASSERT_TRUE(line.has_value());
  EXPECT_NEAR(line->direction.x, 0, 1e-12);
  EXPECT_NEAR(line->direction.y, 1, 1e-12);
  EXPECT_NEAR(line->direction.z, 0, 1e-12);
  EXPECT_NEAR(line->point.x, 5, 1e-6);
  EXPECT_NEAR(line->point.y, 0, 1e-12);
  EXPECT_NEAR(line->point.z, 0, 1e-6);
}

TEST(GraphPlanePlaneLine, GeneralPositionLiesOnBothPlanesNearestMidpoint) {
  const Vec3f ci{1.5f, -2, 0.25f}, ni = normalized({1, 2, 3});
  const Vec3f cj{-0.5f, 4, 2}, nj = normalized({-2, 0.5f, 1});
  const auto line = plane_plane_line(ci, ni, cj, nj);
  ASSERT_TRUE(line.has_value());
  for (double t : {-3.0, 0.0, 2.5}) {
    const Vec3d p = line->point + line->direction * t;
    EXPECT_NEAR(plane_residual(p, ci, ni), 0, 1e-12);
    EXPECT_NEAR(plane_residual(p, cj, nj), 0, 1e-12);
  }
  EXPECT_NEAR(norm(line->direction), 1, 1e-15);
  const Vec3d mid = (to_vec3d(ci) + to_vec3d(cj)) * 0.5;
  EXPECT_NEAR(dot(line->point - mid, line->direction), 0, 1e-12);
}

TEST(GraphPlanePlaneLine, SwappingSplatsReversesDirectionKeepsPoint) {
  const Vec3f ci{1.5f, -2, 0.25f}, ni = normalized({1, 2, 3});
  const Vec3f cj{-0.5f, 4, 2}, nj = normalized({-2, 0.5f, 1});
  const auto a = plane_plane_line(ci, ni, cj, nj);
  const auto b = plane_plane_line(cj, nj, ci, ni);
  ASSERT_TRUE(a && b);
  EXPECT_NEAR(norm(a->point - b->point), 0, 1e-12);
  EXPECT_NEAR(norm(a->direction + b->direction), 0, 1e-15);
}

TEST(GraphPlanePlaneLine, ParallelCoincidentZeroAndNanGiveNoLine) {
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}));   // parallel
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {0, 0, 1}, {3, 4, 0}, {0, 0, 1}));   // coincident
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}));  // antiparallel
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}));   // zero normal
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {nan, 0, 1}, {0, 0, 1}, {1, 0, 0}));
  // Nearly parallel: 1e-4 rad apart is sin² = 1e-8, a line by default, none at min_sin2 = 1e-6.
  const Vec3f tilted{std::sin(1e-4f), 0, std::cos(1e-4f)};
  EXPECT_TRUE(plane_plane_line({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, tilted));
  EXPECT_FALSE(plane_plane_line({0, 0, 0}, {0, 0, 1}, {0, 0, 1}, tilted, 1e-6));
}

}  // namespace
}  // namespace splatkit::graph
