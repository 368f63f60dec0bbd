// line_disc_segment ([IvoMSc] eq. 4.12) and line_ellipse_segment (eq. 4.11): chords of a line
// through a splat.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "graph/line_disc_segment.h"
#include "graph/line_ellipse_segment.h"

namespace splatkit::graph {
namespace {

const Vec3f kZ{0, 0, 1};

TEST(GraphLineDiscSegment, ChordOfCircle) {
  // Radius 5, line x = 3: half-chord sqrt(25 - 9) = 4 around t = 10.
  const auto s = line_disc_segment({{3, -10, 0}, {0, 1, 0}}, {0, 0, 0}, kZ, 5);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->t0, 6);
  EXPECT_EQ(s->t1, 14);
}

TEST(GraphLineDiscSegment, ThroughCentreOffCentreDiscAndScaledDirection) {
  auto s = line_disc_segment({{0, 0, 0}, {-1, 0, 0}}, {0, 0, 0}, kZ, 5);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->t0, -5);
  EXPECT_EQ(s->t1, 5);
  // Centre (1, 2, 0); direction of length 2 halves the parameter interval.
  s = line_disc_segment({{4, -8, 0}, {0, 2, 0}}, {1, 2, 0}, kZ, 5);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->t0, 3);
  EXPECT_EQ(s->t1, 7);
}

TEST(GraphLineDiscSegment, NormalComponentIsDropped) {
  // The same line lifted 7 along the normal: its projection is the first test's line.
  const auto s = line_disc_segment({{3, -10, 7}, {0, 1, 0}}, {0, 0, 0}, kZ, 5);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->t0, 6);
  EXPECT_EQ(s->t1, 14);
}

TEST(GraphLineDiscSegment, MissTangentAndDegenerate) {
  EXPECT_FALSE(line_disc_segment({{6, 0, 0}, {0, 1, 0}}, {0, 0, 0}, kZ, 5));
  const auto tangent = line_disc_segment({{5, 0, 0}, {0, 1, 0}}, {0, 0, 0}, kZ, 5);
  ASSERT_TRUE(tangent);
  EXPECT_EQ(tangent->t0, 0);
  EXPECT_EQ(tangent->t1, 0);
  EXPECT_FALSE(line_disc_segment({{0, 0, 0}, {0, 0, 1}}, {0, 0, 0}, kZ, 5));  // perpendicular
  EXPECT_FALSE(line_disc_segment({{0, 0, 0}, {1, 0, 0}}, {0, 0, 0}, kZ, 0));  // radius 0
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(line_disc_segment({{0, 0, 0}, {1, 0, 0}}, {nan, 0, 0}, kZ, 5));
}

TEST(GraphLineEllipseSegment, ChordOfAxisAlignedEllipse) {
  // Semi-axes 5 (x) and 3 (y), centre (1, 2, 0); line x = 4: u = 3/5, v = ±4/5, y = 2 ± 12/5.
  const auto s =
      line_ellipse_segment({{4, -8, 0}, {0, 1, 0}}, {1, 2, 0}, {1, 0, 0}, {0, 1, 0}, 5, 3);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->t0, 10 - 2.4, 1e-12);
  EXPECT_NEAR(s->t1, 10 + 2.4, 1e-12);
}

TEST(GraphLineEllipseSegment, RotatedAxes) {
  // Long axis along y (5), short along -x (3): a line along x through the centre spans ±3.
  const auto s =
      line_ellipse_segment({{0, 0, 0}, {1, 0, 0}}, {0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, 5, 3);
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->t0, -3);
  EXPECT_DOUBLE_EQ(s->t1, 3);
  // The same line misses the ellipse when moved 5.5 along y, beyond the long semi-axis.
  EXPECT_FALSE(
      line_ellipse_segment({{0, 5.5, 0}, {1, 0, 0}}, {0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, 5, 3));
}

TEST(GraphLineEllipseSegment, EqualSemiAxesMatchCircle) {
  const Line3 line{{0.5, -1, 0.25}, {0.6, 0.8, 0}};
  const Vec3f c{0.25f, 0.5f, 0};
  const auto circle = line_disc_segment(line, c, kZ, 2);
  const float h = std::sqrt(0.5f);
  const auto ellipse = line_ellipse_segment(line, c, {h, h, 0}, {-h, h, 0}, 2, 2);
  ASSERT_TRUE(circle && ellipse);
  EXPECT_NEAR(circle->t0, ellipse->t0, 1e-6);
  EXPECT_NEAR(circle->t1, ellipse->t1, 1e-6);
}

TEST(GraphLineEllipseSegment, DegenerateInputs) {
  const Line3 line{{0, 0, 0}, {1, 0, 0}};
  EXPECT_FALSE(line_ellipse_segment(line, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0, 3));
  EXPECT_FALSE(line_ellipse_segment({{0, 0, 0}, {0, 0, 1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5, 3));
  const auto tangent =
      line_ellipse_segment({{0, 3, 0}, {1, 0, 0}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5, 3);
  ASSERT_TRUE(tangent);
  EXPECT_EQ(tangent->t0, 0);
  EXPECT_EQ(tangent->t1, 0);
}

}  // namespace
}  // namespace splatkit::graph
