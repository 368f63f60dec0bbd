// Rank selection of points along an axis (splatkit/select_rank.h) against std::nth_element with
// the (coordinate, index) order it defines, on clouds with ties everywhere (coordinates snapped
// to a coarse grid, -0 beside +0, exact duplicates) and on ranges long enough for the sampled
// pivots; and the point bounds, serial and in parallel chunks, against a plain loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "splatkit/select_rank.h"

namespace splatkit {
namespace {

// n points whose coordinates take few values (a 1/4 grid in [-2, 2], -0 for a quarter of the
// zeros), a tenth of them exact copies of earlier ones.
std::vector<RankedPoint> tied_points(std::size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_int_distribution<int> cell(-8, 8);
  std::vector<Vec3f> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && g() % 10 == 0) {
      p[i] = p[g() % i];
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const float v = static_cast<float>(cell(g)) / 4;
      p[i][k] = v == 0 && g() % 4 == 0 ? -0.0f : v;
    }
  }
  std::vector<RankedPoint> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = RankedPoint::make(p[i], static_cast<uint32_t>(i));
  return out;
}

// The order select_rank promises: coordinate (-0 equal to +0), then index.
std::pair<float, uint32_t> key(const RankedPoint& q, int axis) {
  const float c = q.coord(axis);
  return {c == 0 ? 0.0f : c, q.index()};
}

void expect_selected(std::vector<RankedPoint> pts, std::size_t nth, int axis) {
  std::vector<RankedPoint> want = pts;
  const auto before = [axis](const RankedPoint& a, const RankedPoint& b) {
    return key(a, axis) < key(b, axis);
  };
  std::nth_element(want.begin(), want.begin() + static_cast<std::ptrdiff_t>(nth), want.end(),
                   before);
  select_rank(pts.data(), pts.data() + nth, pts.data() + pts.size(), axis);
  // The same point at nth (keys are unique), smaller keys before it, larger after.
  ASSERT_EQ(pts[nth].index(), want[nth].index());
  for (std::size_t i = 0; i < nth; ++i) ASSERT_TRUE(before(pts[i], pts[nth])) << i;
  for (std::size_t i = nth + 1; i < pts.size(); ++i) ASSERT_TRUE(before(pts[nth], pts[i])) << i;
  // Nothing lost or copied: each index once, with its own coordinates.
  std::vector<RankedPoint> got = pts;
  const auto by_index = [](const RankedPoint& a, const RankedPoint& b) {
    return a.index() < b.index();
  };
  std::sort(got.begin(), got.end(), by_index);
  std::sort(want.begin(), want.end(), by_index);
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].xy, want[i].xy);
    ASSERT_EQ(got[i].zi, want[i].zi);
  }
}

TEST(SelectRank, MatchesNthElementOnTiedSmallRanges) {
  for (std::size_t n : {1, 2, 3, 5, 16, 17, 100, 1000}) {
    const std::vector<RankedPoint> pts = tied_points(n, static_cast<unsigned>(n));
    for (int axis = 0; axis < 3; ++axis)
      for (std::size_t nth : {std::size_t{0}, n / 3, n / 2, n - 1}) expect_selected(pts, nth, axis);
  }
}

TEST(SelectRank, MatchesNthElementWithSampledPivots) {
  // Longer than the range cut by sampled pivots (8192), at ranks near both ends and the middle.
  const std::size_t n = 50000;
  const std::vector<RankedPoint> pts = tied_points(n, 7);
  for (int axis = 0; axis < 3; ++axis)
    for (std::size_t nth : {std::size_t{3}, n / 4, n / 2, n - 10}) expect_selected(pts, nth, axis);
}

TEST(SelectRank, PointBoundsSerialAndParallel) {
  std::mt19937 g(11);
  std::normal_distribution<float> d(0, 1000);
  // Below and above the size where the bounds are taken in parallel chunks (2^19 points).
  for (std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{1} << 20}) {
    std::vector<RankedPoint> pts(n);
    Vec3f lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3f p{d(g), d(g), d(g) - 5000};
      pts[i] = RankedPoint::make(p, static_cast<uint32_t>(i));
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
    Vec3f got_lo, got_hi;
    point_bounds(pts.data(), pts.data() + n, got_lo, got_hi);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(got_lo[k], lo[k]) << n << " axis " << k;
      EXPECT_EQ(got_hi[k], hi[k]) << n << " axis " << k;
    }
  }
  EXPECT_EQ(longest_axis({0, 0, 0}, {1, 3, 2}), 1);
  EXPECT_EQ(longest_axis({0, 0, 0}, {2, 2, 2}), 0);  // the first of equal ones
  EXPECT_EQ(longest_axis({0, 0, 0}, {1, 2, 2}), 1);
}

}  // namespace
}  // namespace splatkit
