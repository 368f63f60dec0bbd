// morton_order against a plain sort of (code, number) pairs, on clouds with many equal codes, a
// far outlier (most points in one top-level bucket, sorted in parallel), and the property chunked
// processing rests on: a subset in input order, coded over the whole set's box, keeps its order.
#include "splatkit/morton_order.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "splatkit/deterministic_rng.h"
#include "splatkit/splat_cloud.h"

namespace splatkit {
namespace {

std::vector<Vec3f> cloud(std::size_t n, uint64_t seed, bool snapped) {
  DeterministicRng rng{seed};
  std::vector<Vec3f> pts(n);
  for (auto& p : pts) {
    p = {rng.uniformf(), rng.uniformf(), 0.01f * rng.uniformf()};
    if (snapped)  // 1 mm steps, as LAS coordinates are: many points share a code
      p = {static_cast<float>(rng.next() % 50) * 1e-3f, static_cast<float>(rng.next() % 50) * 1e-3f,
           0.0f};
  }
  return pts;
}

std::vector<uint32_t> sorted_by_code(const std::vector<Vec3f>& pts, const MortonFrame& frame) {
  std::vector<std::pair<uint64_t, uint32_t>> keys(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    keys[i] = {frame.code(pts[i]), static_cast<uint32_t>(i)};
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> order;
  for (const auto& k : keys) order.push_back(k.second);
  return order;
}

MortonFrame frame_of(const std::vector<Vec3f>& pts) {
  const Bounds box = compute_bounds(pts);
  return MortonFrame(box.min, box.max);
}

TEST(MortonOrder, SortsByCodeThenNumber) {
  for (bool snapped : {false, true}) {
    for (std::size_t n : {0, 1, 5, 1000, 300000}) {
      const std::vector<Vec3f> pts = cloud(n, 3 + n, snapped);
      EXPECT_EQ(morton_order(pts), sorted_by_code(pts, frame_of(pts))) << n << " " << snapped;
    }
  }
}

TEST(MortonOrder, OneFarPointPutsTheRestInOneBucketSortedInParallel) {
  std::vector<Vec3f> pts = cloud(1500000, 9, false);
  pts[700000] = {1e6f, 1e6f, 1e6f};
  const std::vector<uint32_t> order = morton_order(pts);
  EXPECT_EQ(order, sorted_by_code(pts, frame_of(pts)));
  EXPECT_EQ(order.back(), 700000u);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_EQ(morton_order(pts), order);
}

TEST(MortonOrder, SortRearrangesThePointsIntoTheOrder) {
  for (bool snapped : {false, true}) {
    const std::vector<Vec3f> pts = cloud(300000, 12, snapped);
    std::vector<Vec3f> sorted = pts;
    const std::vector<uint32_t> order = morton_sort(sorted);
    ASSERT_EQ(order, morton_order(pts)) << snapped;
    ASSERT_EQ(sorted.size(), pts.size());
    for (std::size_t t = 0; t < pts.size(); ++t) ASSERT_EQ(sorted[t], pts[order[t]]) << t;
  }
}

// Every copy (a position an earlier point has, -0 = +0) with its first occurrence, by brute force.
std::vector<DuplicatePoint> copies_of(const std::vector<Vec3f>& pts) {
  std::vector<DuplicatePoint> copies;
  std::vector<uint32_t> firsts;
  for (uint32_t i = 0; i < pts.size(); ++i) {
    const auto it = std::find_if(firsts.begin(), firsts.end(),
                                 [&](uint32_t f) { return same_point(pts[f], pts[i]); });
    if (it == firsts.end())
      firsts.push_back(i);
    else
      copies.push_back({i, *it});
  }
  return copies;
}

TEST(MortonOrder, SortFindsTheCopiesOfEarlierPoints) {
  // Snapped: 2500 positions over 100k points, runs of ~40 equal codes, across the blocks of the
  // search (65536 keys); a long run of one position (sorted, not compared pairwise); -0 and +0.
  std::vector<Vec3f> pts = cloud(100000, 21, true);
  for (std::size_t i = 65000; i < 65600; ++i) pts[i] = {0.0105f, 0.0205f, 0.0f};
  pts[99999] = {-0.0f, 0.0f, -0.0f};
  pts[99998] = {0.0f, -0.0f, 0.0f};
  for (const std::vector<Vec3f>& input : {pts, cloud(2000, 5, false), std::vector<Vec3f>{}}) {
    std::vector<Vec3f> plain = input, with = input;
    std::vector<DuplicatePoint> copies{{1, 2}};
    const std::vector<uint32_t> order = morton_sort(with, copies);
    EXPECT_EQ(order, morton_sort(plain));
    EXPECT_EQ(with, plain);
    const std::vector<DuplicatePoint> expected = copies_of(input);
    EXPECT_EQ(copies.size(), expected.size());
    EXPECT_TRUE(copies == expected) << input.size();
  }
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  std::vector<Vec3f> sorted = pts;
  std::vector<DuplicatePoint> copies;
  morton_sort(sorted, copies);
  EXPECT_TRUE(copies == copies_of(pts));
}

TEST(MortonOrder, ASubsetCodedOverTheWholeBoxKeepsItsPlaceInTheWholeOrder) {
  const std::vector<Vec3f> pts = cloud(20000, 4, true);
  const MortonFrame whole = frame_of(pts);
  const std::vector<uint32_t> order = morton_order(pts);
  std::vector<Vec3f> subset;
  std::vector<uint32_t> number;
  for (uint32_t i = 0; i < pts.size(); i += 3) {
    subset.push_back(pts[i]);
    number.push_back(i);
  }
  std::vector<uint32_t> expected;  // the whole order restricted to the subset
  for (uint32_t i : order)
    if (i % 3 == 0) expected.push_back(i);
  std::vector<uint32_t> got;
  for (uint32_t s : sorted_by_code(subset, whole)) got.push_back(number[s]);
  EXPECT_EQ(got, expected);
}

}  // namespace
}  // namespace splatkit
