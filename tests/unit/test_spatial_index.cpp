// SpatialIndex against brute force: exact (squared distance, index) orders, on random clouds and
// the degenerate ones (duplicates, identical points, collinear, fewer points than k, empty).
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "simd_level_test.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

using Rng = DeterministicRng;

std::vector<Vec3f> random_cloud(std::size_t n, uint64_t seed) {
  Rng rng{seed};
  std::vector<Vec3f> pts(n);
  for (auto& p : pts) p = {rng.uniformf(), rng.uniformf(), rng.uniformf()};
  return pts;
}

// Coordinates snapped to a 4-step grid: many duplicates and many exactly equal distances.
std::vector<Vec3f> grid_cloud(std::size_t n, uint64_t seed) {
  Rng rng{seed};
  std::vector<Vec3f> pts(n);
  for (auto& p : pts) {
    p = {static_cast<float>(rng.next() % 4), static_cast<float>(rng.next() % 4),
         static_cast<float>(rng.next() % 4)};
  }
  return pts;
}

using Ranked = std::vector<std::pair<float, uint32_t>>;

// Every point with its squared distance to q, sorted by (distance, index).
Ranked brute_rank(const std::vector<Vec3f>& pts, const Vec3f& q) {
  Ranked all;
  for (uint32_t j = 0; j < pts.size(); ++j) all.push_back({squared_distance(pts[j], q), j});
  std::sort(all.begin(), all.end());
  return all;
}

void expect_knn_matches(const SpatialIndex& index, const std::vector<Vec3f>& pts, const Vec3f& q,
                        std::size_t k) {
  Ranked expected = brute_rank(pts, q);
  std::vector<uint32_t> ids(k, 12345);
  std::vector<float> d2(k, -1.0f);
  std::size_t count = index.knn(q, k, ids.data(), d2.data());
  ASSERT_EQ(count, std::min(k, pts.size()));
  for (std::size_t c = 0; c < count; ++c) {
    EXPECT_EQ(ids[c], expected[c].second) << "rank " << c;
    EXPECT_EQ(d2[c], expected[c].first) << "rank " << c;
  }
}

// knn_all's contract: row i = i itself at 0, then the k - 1 nearest others, then kNone / +inf.
void expect_knn_all_matches(const SpatialIndex& index, const std::vector<Vec3f>& pts,
                            std::size_t k) {
  const std::size_t n = pts.size();
  std::vector<uint32_t> ids(n * k);
  std::vector<float> d2(n * k);
  index.knn_all(k, ids, d2);
  for (uint32_t i = 0; i < n; ++i) {
    Ranked others = brute_rank(pts, pts[i]);
    others.erase(std::find(others.begin(), others.end(), std::make_pair(0.0f, i)));
    ASSERT_EQ(ids[i * k], i);
    ASSERT_EQ(d2[i * k], 0.0f);
    for (std::size_t c = 1; c < k; ++c) {
      if (c - 1 < others.size()) {
        ASSERT_EQ(ids[i * k + c], others[c - 1].second) << "point " << i << " column " << c;
        ASSERT_EQ(d2[i * k + c], others[c - 1].first) << "point " << i << " column " << c;
      } else {
        ASSERT_EQ(ids[i * k + c], SpatialIndex::kNone);
        ASSERT_EQ(d2[i * k + c], kInf);
      }
    }
  }
}

TEST(SpatialIndex, KnnMatchesBruteForceOnRandomClouds) {
  for (uint64_t seed : {1, 2, 3}) {
    std::vector<Vec3f> pts = random_cloud(1500, seed);
    for (std::size_t leaf : {1, 5, 16}) {
      SpatialIndex index(pts, leaf);
      ASSERT_EQ(index.size(), pts.size());
      std::vector<Vec3f> queries = random_cloud(40, seed + 100);
      for (std::size_t k : {1, 5, 16, 33}) {
        for (const Vec3f& q : queries) expect_knn_matches(index, pts, q, k);
        // A query far outside the cloud exercises pruning from the outside.
        expect_knn_matches(index, pts, {3.0f, -2.0f, 0.5f}, k);
      }
    }
  }
}

TEST(SpatialIndex, KnnAllMatchesBruteForce) {
  std::vector<Vec3f> pts = random_cloud(700, 7);
  for (std::size_t leaf : {1, 2, 16}) {
    SpatialIndex index(pts, leaf);
    for (std::size_t k : {1, 5, 16, 33}) expect_knn_all_matches(index, pts, k);
  }
}

TEST(SpatialIndex, DuplicatesAndTiesGoToTheSmallerIndex) {
  std::vector<Vec3f> pts = grid_cloud(400, 11);  // 64 distinct positions, ~6 copies each
  SpatialIndex index(pts, 4);
  for (std::size_t k : {1, 5, 16, 33}) {
    expect_knn_all_matches(index, pts, k);
    expect_knn_matches(index, pts, {1.0f, 2.0f, 1.0f}, k);
    expect_knn_matches(index, pts, {1.5f, 1.5f, 1.5f}, k);  // equidistant from 8 grid nodes
  }
}

// Uneven density: a dense cluster, a sparse background, a plane patch and far outliers, so that
// a leaf's shared candidate set (guessed from the previous leaf) often misses, is too large, or
// spans leaves split across query blocks — every row must still equal brute force.
std::vector<Vec3f> uneven_cloud(uint64_t seed) {
  Rng rng{seed};
  std::vector<Vec3f> pts;
  for (int i = 0; i < 500; ++i)
    pts.push_back({0.3f + 0.01f * rng.uniformf(), 0.3f + 0.01f * rng.uniformf(),
                   0.3f + 0.01f * rng.uniformf()});
  for (int i = 0; i < 300; ++i) pts.push_back({rng.uniformf(), rng.uniformf(), rng.uniformf()});
  for (int i = 0; i < 300; ++i) pts.push_back({rng.uniformf(), rng.uniformf(), 0.75f});
  for (int i = 0; i < 12; ++i)
    pts.push_back({100.0f * rng.uniformf(), -50.0f, 30.0f * rng.uniformf()});
  return pts;
}

TEST(SpatialIndex, KnnAllMatchesBruteForceOnUnevenDensity) {
  std::vector<Vec3f> pts = uneven_cloud(61);
  for (std::size_t leaf : {3, 32, 700}) {
    SpatialIndex index(pts, leaf);
    for (std::size_t k : {2, 16, 40}) expect_knn_all_matches(index, pts, k);
  }
  // Leaves larger than a query block: blocks start and end inside leaves.
  std::vector<Vec3f> more = uneven_cloud(62);
  more.insert(more.end(), pts.begin(), pts.end());
  expect_knn_all_matches(SpatialIndex(more, 1500), more, 16);
}

TEST(SpatialIndex, ManyCopiesAmongOtherPoints) {
  // More copies of one point than fit one row: long runs of equal distances in the batch ranking.
  std::vector<Vec3f> pts = random_cloud(300, 71);
  pts.insert(pts.begin() + 100, 200, Vec3f{0.5f, 0.5f, 0.5f});
  for (std::size_t leaf : {8, 32}) {
    SpatialIndex index(pts, leaf);
    for (std::size_t k : {16, 90}) expect_knn_all_matches(index, pts, k);
  }
}

TEST(SpatialIndex, SortedReversedAndOrganPipeInputs) {
  // Orders that trouble median-of-three selection while building, and runs of equal coordinates.
  std::vector<Vec3f> sorted;
  for (int i = 0; i < 1200; ++i)
    sorted.push_back(
        {static_cast<float>(i), static_cast<float>(i % 7), static_cast<float>(i / 400)});
  std::vector<Vec3f> reversed(sorted.rbegin(), sorted.rend());
  std::vector<Vec3f> organ_pipe(sorted.begin(), sorted.begin() + 600);
  organ_pipe.insert(organ_pipe.end(), reversed.begin() + 600, reversed.end());
  for (const auto* cloud : {&sorted, &reversed, &organ_pipe}) {
    SpatialIndex index(*cloud, 8);
    expect_knn_all_matches(index, *cloud, 9);
  }
}

TEST(SpatialIndex, SampledSelectionOnLongRangesWithRunsOfEqualCoordinates) {
  // Ranges over 4096 points are narrowed by pivots from a sample (select_nth): sorted input, few
  // distinct coordinates on the widest axis (the pivots equal: one run), and one point apart.
  std::vector<Vec3f> steps, two_values;
  for (int i = 0; i < 4400; ++i) {
    steps.push_back({static_cast<float>(i / 700), static_cast<float>(i % 13) * 0.01f,
                     static_cast<float>(i % 7) * 0.01f});
    two_values.push_back({i == 2345 ? 0.5f : static_cast<float>(i % 2),
                          static_cast<float>((i * 37) % 101) * 1e-3f, 0.0f});
  }
  std::vector<Vec3f> reversed(steps.rbegin(), steps.rend());
  for (const auto* cloud : {&steps, &reversed, &two_values})
    expect_knn_all_matches(SpatialIndex(*cloud, 8), *cloud, 9);
  const std::vector<Vec3f> same(4400, Vec3f{1, 2, 3});
  expect_knn_all_matches(SpatialIndex(same, 32), same, 5);
}

TEST(SpatialIndex, AllPointsIdentical) {
  std::vector<Vec3f> pts(100, Vec3f{0.25f, -1.0f, 3.0f});
  SpatialIndex index(pts, 8);
  std::vector<uint32_t> ids(16);
  ASSERT_EQ(index.knn(pts[0], 16, ids.data(), nullptr), 16u);
  for (uint32_t c = 0; c < 16; ++c) EXPECT_EQ(ids[c], c);
  expect_knn_all_matches(index, pts, 16);
}

TEST(SpatialIndex, CollinearPoints) {
  std::vector<Vec3f> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({0.5f * static_cast<float>((i * 37) % 300), 1, 2});
  SpatialIndex index(pts, 3);
  expect_knn_all_matches(index, pts, 5);
  expect_knn_all_matches(index, pts, 16);
  expect_knn_matches(index, pts, {10.25f, 0, 0}, 7);
}

TEST(SpatialIndex, FewerPointsThanK) {
  std::vector<Vec3f> pts = random_cloud(5, 3);
  SpatialIndex index(pts);
  expect_knn_matches(index, pts, {0.5f, 0.5f, 0.5f}, 16);
  expect_knn_all_matches(index, pts, 16);
  SpatialIndex single(std::vector<Vec3f>{{1, 2, 3}});
  expect_knn_all_matches(single, {{1, 2, 3}}, 4);
}

TEST(SpatialIndex, EmptyCloud) {
  SpatialIndex index(std::vector<Vec3f>{});
  EXPECT_EQ(index.size(), 0u);
  uint32_t id = 7;
  EXPECT_EQ(index.knn({0, 0, 0}, 5, &id, nullptr), 0u);
  std::vector<uint32_t> ids;
  index.knn_all(16, ids);
  index.radius({0, 0, 0}, 1.0f, ids);
  EXPECT_TRUE(ids.empty());
  NeighborGraph graph = index.sphere_overlaps({});
  EXPECT_EQ(graph.offsets, std::vector<uint64_t>{0});
  EXPECT_EQ(SpatialIndex().size(), 0u);
}

TEST(SpatialIndex, RadiusMatchesBruteForce) {
  std::vector<Vec3f> pts = random_cloud(2000, 5);
  std::vector<Vec3f> grid = grid_cloud(300, 6);
  for (const auto* cloud : {&pts, &grid}) {
    SpatialIndex index(*cloud, 6);
    for (const Vec3f& q : random_cloud(30, 9)) {
      for (float r : {0.0f, 0.05f, 0.2f, 1.0f, 2.5f}) {
        Ranked expected = brute_rank(*cloud, q * 3.0f);
        std::vector<uint32_t> ids;
        std::vector<float> d2;
        index.radius(q * 3.0f, r, ids, &d2);
        std::size_t inside = 0;
        while (inside < expected.size() && expected[inside].first <= r * r) ++inside;
        ASSERT_EQ(ids.size(), inside);
        for (std::size_t c = 0; c < inside; ++c) {
          ASSERT_EQ(ids[c], expected[c].second);
          ASSERT_EQ(d2[c], expected[c].first);
        }
      }
    }
    // A radius exactly equal to a grid distance includes the points at that distance.
    if (cloud == &grid) {
      std::vector<uint32_t> ids;
      index.radius({0, 0, 0}, 1.0f, ids);
      std::size_t expected = std::count_if(grid.begin(), grid.end(),
                                           [](const Vec3f& p) { return squared_norm(p) <= 1.0f; });
      EXPECT_EQ(ids.size(), expected);
    }
  }
}

NeighborGraph brute_overlaps(const std::vector<Vec3f>& pts, const std::vector<float>& radii) {
  NeighborGraph graph;
  graph.offsets.push_back(0);
  for (uint32_t i = 0; i < pts.size(); ++i) {
    for (uint32_t j = 0; j < pts.size(); ++j) {
      float sum = radii[i] + radii[j];
      if (j != i && squared_distance(pts[i], pts[j]) < sum * sum) graph.neighbors.push_back(j);
    }
    graph.offsets.push_back(graph.neighbors.size());
  }
  return graph;
}

TEST(SpatialIndex, SphereOverlapsMatchBruteForce) {
  std::vector<Vec3f> pts = random_cloud(1200, 21);
  Rng rng{22};
  std::vector<float> radii(pts.size());
  // Long-tailed radii: most small, a few covering much of the cloud, some zero.
  for (std::size_t i = 0; i < radii.size(); ++i) {
    float u = rng.uniformf();
    radii[i] = i % 97 == 0 ? 0.3f * u : (i % 13 == 0 ? 0.0f : 0.08f * u);
  }
  // Equal radii too: every leaf answers from its shared candidate set.
  std::vector<float> equal_radii(pts.size(), 0.05f);
  for (const auto* r : {&radii, &equal_radii}) {
    for (std::size_t leaf : {1, 16, 64}) {
      SpatialIndex index(pts, leaf);
      NeighborGraph graph = index.sphere_overlaps(*r);
      NeighborGraph expected = brute_overlaps(pts, *r);
      EXPECT_EQ(graph.offsets, expected.offsets);
      EXPECT_EQ(graph.neighbors, expected.neighbors);
      EXPECT_GT(graph.neighbors.size(), pts.size());  // the test is not vacuous
    }
  }
}

// The batch kNN and the sphere overlaps at every SIMD level the CPU has (simd_level() capped):
// each vector path against brute force, on random, duplicate-heavy and uneven clouds.
using SpatialIndexAt = SimdLevelTest;
INSTANTIATE_TEST_SUITE_P(Simd, SpatialIndexAt, kEverySimdLevel, simd_level_param_name);

TEST_P(SpatialIndexAt, KnnMatchesBruteForce) {
  const std::vector<Vec3f> random = random_cloud(900, 81), dups = grid_cloud(400, 82);
  for (std::size_t k : {5, 16, 40}) {
    expect_knn_all_matches(SpatialIndex(random, 16), random, k);
    expect_knn_all_matches(SpatialIndex(dups, 8), dups, k);
    expect_knn_all_matches(SpatialIndex(uneven_cloud(83), 32), uneven_cloud(83), k);
    expect_knn_matches(SpatialIndex(random, 16), random, {0.5f, 0.25f, 0.125f}, k);
  }
}

TEST_P(SpatialIndexAt, SphereOverlapsMatchBruteForce) {
  std::vector<Vec3f> pts = random_cloud(1500, 84);
  Rng rng{85};
  std::vector<float> radii(pts.size());
  for (std::size_t i = 0; i < radii.size(); ++i)
    radii[i] =
        i % 89 == 0 ? 0.3f + 0.1f * rng.uniformf() : 0.06f * rng.uniformf();  // rows past 160
  const NeighborGraph graph = SpatialIndex(pts, 32).sphere_overlaps(radii);
  const NeighborGraph expected = brute_overlaps(pts, radii);
  EXPECT_EQ(graph.offsets, expected.offsets);
  EXPECT_EQ(graph.neighbors, expected.neighbors);
  std::size_t longest = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) longest = std::max(longest, expected.row(i).size());
  EXPECT_GT(longest, 160u);
}

// A few points very far from the rest (1e20, -1e30, copies at 3e25, whose squared distances to
// the others overflow to +inf): every kNN row and the overlap graph stay exact.
TEST_P(SpatialIndexAt, FarOutliersKeepAnswersExact) {
  std::vector<Vec3f> pts = random_cloud(2000, 86);
  pts[0] = {1e20f, 0, 0};
  pts[1500] = {-1e30f, 0.5f, 0.5f};
  pts[1501] = pts[1999] = {3e25f, -3e25f, 1};
  expect_knn_all_matches(SpatialIndex(pts), pts, 16);
  std::vector<float> radii(pts.size(), 0.04f);
  radii[0] = 1e20f;
  const NeighborGraph graph = SpatialIndex(pts).sphere_overlaps(radii);
  const NeighborGraph expected = brute_overlaps(pts, radii);
  EXPECT_EQ(graph.offsets, expected.offsets);
  EXPECT_EQ(graph.neighbors, expected.neighbors);
  EXPECT_EQ(expected.row(1501).size(), 1u);  // the far copies overlap each other only
}

TEST(SpatialIndex, SphereOverlapsAreStrict) {
  // Spheres that only touch (distance == r_i + r_j exactly) do not overlap; duplicates with
  // radius 0 do not either; duplicates with a positive radius do.
  std::vector<Vec3f> pts = {{0, 0, 0}, {2, 0, 0}, {2, 0, 0}, {5, 0, 0}, {5, 0, 0}};
  std::vector<float> radii = {1, 1, 1, 0, 0};
  NeighborGraph graph = SpatialIndex(pts, 1).sphere_overlaps(radii);
  EXPECT_EQ(graph.offsets, (std::vector<uint64_t>{0, 0, 1, 2, 2, 2}));
  EXPECT_EQ(graph.neighbors, (std::vector<uint32_t>{2, 1}));
  EXPECT_THROW(SpatialIndex(pts).sphere_overlaps(std::vector<float>{1, 1}), std::invalid_argument);
  EXPECT_THROW(SpatialIndex(pts).sphere_overlaps(std::vector<float>{1, 1, -1, 0, 0}),
               std::invalid_argument);
}

TEST(SpatialIndex, SameResultsForAnyThreadCount) {
  std::vector<Vec3f> pts = random_cloud(20000, 31);
  SpatialIndex index(pts);
  std::vector<float> radii(pts.size(), 0.02f);
  auto run = [&](int threads) {
    std::vector<uint32_t> ids(pts.size() * 16);
    std::vector<float> d2(pts.size() * 16);
    NeighborGraph graph;
    tbb::task_arena(threads).execute([&] {
      index.knn_all(16, ids, d2);
      graph = index.sphere_overlaps(radii);
    });
    return std::make_tuple(ids, d2, graph.offsets, graph.neighbors);
  };
  auto one = run(1);
  EXPECT_EQ(run(2), one);
}

TEST(SpatialIndex, KnnBlocksCoverEveryPointOnce) {
  std::vector<Vec3f> pts = random_cloud(5000, 41);
  SpatialIndex index(pts);
  std::vector<std::atomic<int>> seen(pts.size());
  std::vector<uint32_t> expected_ids(pts.size() * 5);
  index.knn_all(5, expected_ids);
  std::atomic<bool> rows_match{true};
  index.for_each_knn_block(5, [&](std::span<const uint32_t> queries, std::span<const uint32_t> ids,
                                  std::span<const float> d2) {
    EXPECT_LE(queries.size(), 1024u);
    EXPECT_EQ(ids.size(), queries.size() * 5);
    EXPECT_EQ(d2.size(), queries.size() * 5);
    for (std::size_t r = 0; r < queries.size(); ++r) {
      seen[queries[r]]++;
      if (!std::equal(ids.begin() + r * 5, ids.begin() + r * 5 + 5,
                      expected_ids.begin() + queries[r] * 5)) {
        rows_match = false;
      }
    }
  });
  for (const auto& s : seen) ASSERT_EQ(s.load(), 1);
  EXPECT_TRUE(rows_match);
}

TEST(SpatialIndex, RejectsBadInput) {
  std::vector<Vec3f> pts = {{0, 0, 0}, {1, std::nanf(""), 0}};
  EXPECT_THROW(SpatialIndex{pts}, Error);
  pts[1] = {kInf, 0, 0};
  EXPECT_THROW(SpatialIndex{pts}, Error);
  pts[1] = {1, 0, 0};
  EXPECT_THROW(SpatialIndex(pts, 0), std::invalid_argument);
  SpatialIndex index(pts);
  std::vector<uint32_t> ids;
  EXPECT_THROW(index.radius({0, 0, 0}, -1.0f, ids), std::invalid_argument);
  EXPECT_THROW(index.radius({0, 0, 0}, std::nanf(""), ids), std::invalid_argument);
  uint32_t id = 7;
  EXPECT_EQ(index.knn({std::nanf(""), 0, 0}, 1, &id, nullptr), 0u);
  EXPECT_EQ(index.knn({0, kInf, 0}, 1, &id, nullptr), 0u);
  ids.push_back(3);
  index.radius({0, 0, -kInf}, 1.0f, ids);
  EXPECT_TRUE(ids.empty());
  std::vector<uint32_t> too_small(3);
  EXPECT_THROW(index.knn_all(2, too_small), std::invalid_argument);
  EXPECT_LT(index.memory_bytes(), 1000u);
}

TEST(SpatialIndex, MemoryStaysUnderTwentyBytesPerPoint) {
  std::vector<Vec3f> pts = random_cloud(100000, 51);
  SpatialIndex index(pts);
  EXPECT_LE(index.memory_bytes(), 19 * pts.size());
  EXPECT_GE(index.memory_bytes(), 16 * pts.size());
}

}  // namespace
}  // namespace splatkit
