// bound_radii and estimate-normals' --max-radius-ratio on clouds whose density varies 100x.
#include "normals/bound_radii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "normals/estimate_normals.h"
#include "normals/orient_normals_mst.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit {
namespace {

// n points on the unit square, density growing 100x from x = 0 to x = 1 (x drawn by the inverse
// CDF of a density proportional to 100^x), i.i.d.; `stray` points 0.05-0.3 above it.
SplatCloud gradient_plane(std::size_t n, std::size_t stray, uint64_t seed) {
  SplatCloud c;
  DeterministicRng rng(seed);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::log1p(rng.uniform() * 99.0) / std::log(100.0);
    c.positions.push_back({static_cast<float>(x), static_cast<float>(rng.uniform()), 0.0f});
  }
  for (std::size_t i = 0; i < stray; ++i)
    c.positions.push_back({static_cast<float>(rng.uniform()), static_cast<float>(rng.uniform()),
                           static_cast<float>(rng.uniform(0.05, 0.3))});
  return c;
}

// The ratio of every radius to its 8 neighbours' median, sorted.
std::vector<float> ratios(const SplatCloud& c) {
  const SpatialIndex index(c.positions);
  const std::vector<float> m = neighbour_median_radii(index, c.radii, 8);
  std::vector<float> r(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) r[i] = c.radii[i] / m[i];
  std::sort(r.begin(), r.end());
  return r;
}
float quantile(const std::vector<float>& sorted, double q) {
  return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

TEST(NormalsBoundRadii, MeasuredDefaultOnA100xDensityGradient) {
  // Unbounded radii of a clean gradient: how far above its neighbours' a radius goes where the
  // density only varies smoothly (the default must leave these alone), and with 0.2 % strays.
  NormalOptions off;
  off.max_radius_ratio = 0;
  off.orient = NormalOrientation::kNone;
  SplatCloud clean = gradient_plane(30000, 0, 1);
  estimate_normals(clean, off);
  const std::vector<float> r = ratios(clean);
  std::printf("clean 100x gradient, unbounded: ratio p50 %.2f p99 %.2f p99.9 %.2f max %.2f\n",
              quantile(r, 0.5), quantile(r, 0.99), quantile(r, 0.999), r.back());
  SplatCloud strays = gradient_plane(30000, 60, 1);
  estimate_normals(strays, off);
  const std::vector<float> s = ratios(strays);
  std::printf("with 60 strays, unbounded: ratio p99.9 %.2f max %.2f\n", quantile(s, 0.999),
              s.back());
  // The default bounds the strays and leaves (almost) all of the clean gradient alone.
  EXPECT_LE(quantile(r, 0.999), kDefaultMaxRadiusRatio);
  EXPECT_GT(s.back(), 2 * kDefaultMaxRadiusRatio);

  NormalOptions on = off;
  on.max_radius_ratio = kDefaultMaxRadiusRatio;
  SplatCloud bounded = gradient_plane(30000, 60, 1);
  const NormalReport rep = estimate_normals(bounded, on);
  const std::vector<float> b = ratios(bounded);
  std::printf("with 60 strays, bounded at %.1f: %zu radii lowered, max ratio %.3f\n",
              kDefaultMaxRadiusRatio, rep.bounded_radii, b.back());
  EXPECT_LE(b.back(), kDefaultMaxRadiusRatio * (1 + 1e-6f));
  EXPECT_EQ(rep.radii_over_bound, 0u);
  EXPECT_GT(rep.bounded_radii, 0u);
  EXPECT_LT(rep.bounded_radii, bounded.size() / 100);
  for (const float x : bounded.radii) EXPECT_GT(x, 0.0f);
  SplatCloud clean_on = gradient_plane(30000, 0, 1);
  const NormalReport rc = estimate_normals(clean_on, on);
  // The wider bound (3 × the median of the 32 nearest, kWideBoundRatio) lowers the largest
  // splats of the gradient's sparse side where it meets the dense one: 0.4 % of them here.
  EXPECT_LT(rc.bounded_radii, clean_on.size() / 100) << "the bound cut into a clean gradient";
  // Afterwards no radius is above 3 × the median radius of its 32 nearest points.
  const SpatialIndex index(clean_on.positions);
  const std::vector<float> wide = neighbour_median_radii(index, clean_on.radii, kWideBoundK);
  for (std::size_t i = 0; i < wide.size(); ++i)
    ASSERT_LE(clean_on.radii[i], kWideBoundRatio * wide[i] * (1 + 1e-6f)) << i;
}

TEST(NormalsBoundRadii, CapsAtRatioTimesNeighbourMedianAndScalesEllipses) {
  // A row of points 1 apart with radius 1, one with radius 10: capped at 2 × 1.
  std::vector<Vec3f> p;
  for (int i = 0; i < 12; ++i) p.push_back({static_cast<float>(i), 0, 0});
  const SpatialIndex index(p);
  std::vector<float> radii(12, 1.0f), minor(12, 0.5f);
  radii[5] = 10;
  minor[5] = 5;
  const BoundRadiiResult r = bound_radii(index, radii, minor, 2.0f);
  EXPECT_EQ(r.capped, 1u);
  EXPECT_EQ(r.over, 0u);
  EXPECT_FLOAT_EQ(radii[5], 2.0f);
  EXPECT_FLOAT_EQ(minor[5], 1.0f);
  EXPECT_FLOAT_EQ(radii[4], 1.0f);
}

TEST(NormalsBoundRadii, MediansFromTheOrientationsRowsEqualTheirOwnKnnPass) {
  // estimate_normals bounds the radii with the nearest 8 of the MST orientation's 9-wide rows: the
  // same points as a 9-NN query's, ties included. Clouds with ties everywhere (a 1/64 grid
  // snap), exact duplicates and strays; and fewer points than a row.
  DeterministicRng rng(7);
  for (const std::size_t n : {std::size_t{5}, std::size_t{9}, std::size_t{20000}}) {
    SplatCloud c = gradient_plane(n, n / 400, 3);
    for (Vec3f& q : c.positions)
      for (int a = 0; a < 3; ++a) q[a] = std::round(q[a] * 64) / 64;
    for (std::size_t i = 0; i < n / 40; ++i) c.positions.push_back(c.positions[i * 7]);
    std::vector<float> radii(c.size());
    for (float& r : radii) r = static_cast<float>(rng.uniform(0.01, 1.0));
    const SpatialIndex index(c.positions);
    const ShrinkableArray rows = orient_knn_rows(
        [&](std::size_t k, std::span<uint32_t> out) { index_knn_rows(index, k, out); }, c.size(),
        kOrientK);
    const std::size_t width = std::min(kOrientK, c.size()) - 1;
    ASSERT_EQ(rows.size(), c.size() * width);
    const std::vector<float> from_rows = row_median_radii(
        std::span<const uint32_t>(rows.data(), rows.size()), width, radii, kBoundRadiiK);
    const std::vector<float> own = neighbour_median_radii(index, radii, kBoundRadiiK);
    ASSERT_EQ(from_rows.size(), own.size());
    for (std::size_t i = 0; i < own.size(); ++i)
      ASSERT_EQ(from_rows[i], own[i]) << "point " << i << " of " << c.size();
  }
}

TEST(NormalsBoundRadii, WideBoundFindsAgainOnlyTheMediansThatCanChange) {
  // bound_wide_radii finds a candidate's k nearest again in a later pass only when a radius
  // changed within its k-th neighbour's distance: the same radii, minor radii and counts as
  // every candidate's median found again in every pass. Random radii (many capped, over several
  // passes), ties everywhere (a 1/64 grid snap), duplicates and strays.
  DeterministicRng rng(11);
  for (const std::size_t n : {std::size_t{40}, std::size_t{8000}}) {
    SplatCloud c = gradient_plane(n, n / 200, 5);
    for (Vec3f& q : c.positions)
      for (int a = 0; a < 3; ++a) q[a] = std::round(q[a] * 64) / 64;
    for (std::size_t i = 0; i < n / 40; ++i) c.positions.push_back(c.positions[i * 7]);
    std::vector<float> radii(c.size()), minor(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      radii[i] = static_cast<float>(std::exp(rng.uniform(-3.0, 1.5)));
      minor[i] = radii[i] / 2;
    }
    const SpatialIndex index(c.positions);
    const float ratio = 1.5f;
    const std::size_t k = kWideBoundK, passes = 4;
    std::vector<float> wide_r = radii, wide_m = minor;
    const BoundRadiiResult wide =
        bound_wide_radii(index, c.positions, wide_r, wide_m, ratio, k, passes);
    // The candidates as bound_wide_radii chooses them, their medians found in full each pass.
    std::vector<float> sorted = radii;
    std::sort(sorted.begin(), sorted.end());
    const float floor = ratio * sorted[c.size() / 50];
    auto medians = [&](const std::vector<float>& r) {
      std::vector<float> m(r.size(), 0.0f);
      std::vector<uint32_t> row(k + 1);
      for (std::size_t i = 0; i < r.size(); ++i) {
        if (!(radii[i] > floor)) continue;
        const std::size_t found = index.knn(c.positions[i], k + 1, row.data(), nullptr);
        std::vector<float> others;
        for (std::size_t j = 0; j < found && others.size() < k; ++j)
          if (row[j] != i) others.push_back(r[row[j]]);
        std::nth_element(others.begin(), others.begin() + (others.size() - 1) / 2, others.end());
        m[i] = others[(others.size() - 1) / 2];
      }
      return m;
    };
    std::vector<float> full_r = radii, full_m = minor;
    const BoundRadiiResult full = bound_radii(medians, full_r, full_m, ratio, passes);
    EXPECT_GT(full.capped, c.size() / 20);
    EXPECT_GT(full.passes, 1u);
    EXPECT_EQ(wide.capped, full.capped);
    EXPECT_EQ(wide.passes, full.passes);
    EXPECT_EQ(wide.over, full.over);
    EXPECT_EQ(wide_r, full_r);
    EXPECT_EQ(wide_m, full_m);
  }
}

TEST(NormalsBoundRadii, MedianOfEightIsTheFourthSmallestOfEveryOrderAndTie) {
  // Rows of 8 own neighbours: every tuple of {1, 2, 3}^8 (ties), then every permutation of 8
  // distinct values.
  std::vector<std::array<float, 8>> tuples;
  for (int code = 0; code < 6561; ++code) {
    std::array<float, 8> t;
    for (int j = 0, c = code; j < 8; ++j, c /= 3) t[j] = static_cast<float>(1 + c % 3);
    tuples.push_back(t);
  }
  std::array<float, 8> p = {0.5f, 1, 2, 3, 4, 5, 6, 7.5f};
  do tuples.push_back(p);
  while (std::next_permutation(p.begin(), p.end()));
  std::vector<float> radii;
  std::vector<uint32_t> rows;
  for (const auto& t : tuples)
    for (const float v : t) {
      rows.push_back(static_cast<uint32_t>(radii.size()));
      radii.push_back(v);
    }
  rows.resize(radii.size() * 8, 0);  // the values' own points: a row each (of point 0), unread
  const std::vector<float> m = row_median_radii(rows, 8, radii, 8);
  for (std::size_t i = 0; i < tuples.size(); ++i) {
    std::array<float, 8> sorted = tuples[i];
    std::sort(sorted.begin(), sorted.end());
    ASSERT_EQ(m[i], sorted[3]) << "tuple " << i;
  }
}

}  // namespace
}  // namespace splatkit
