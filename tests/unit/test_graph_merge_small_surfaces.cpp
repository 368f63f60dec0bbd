// merge_small_surfaces: fragments join the neighbour they share the most edges with, smallest
// first; chains of fragments end in a large surface; an isolated fragment stays, unless a splat
// of another surface nearly touches it.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "graph/merge_small_surfaces.h"
#include "graph/renumber_surfaces.h"

namespace splatkit::graph {
namespace {

// A graph from an undirected edge list over n splats (rows ascending).
NeighborGraph from_edges(uint32_t n, const std::vector<std::pair<uint32_t, uint32_t>>& edges) {
  std::vector<std::vector<uint32_t>> rows(n);
  for (auto [a, b] : edges) rows[a].push_back(b), rows[b].push_back(a);
  NeighborGraph g;
  g.offsets.push_back(0);
  for (auto& r : rows) {
    std::sort(r.begin(), r.end());
    g.neighbors.insert(g.neighbors.end(), r.begin(), r.end());
    g.offsets.push_back(g.neighbors.size());
  }
  return g;
}

// A path 0-1-...-(n-1).
NeighborGraph path(uint32_t n) {
  std::vector<std::pair<uint32_t, uint32_t>> e;
  for (uint32_t i = 0; i + 1 < n; ++i) e.push_back({i, i + 1});
  return from_edges(n, e);
}

Segmentation labels(const std::vector<uint32_t>& l) {
  return renumber_surfaces(l, *std::max_element(l.begin(), l.end()) + 1);
}

TEST(GraphMergeSmallSurfaces, FragmentJoinsTheNeighbourWithMostEdges) {
  // Surfaces A = {0..4}, F = {5, 6}, B = {7..11}; F has one edge to A (4-5) and, with the extra
  // edges 6-8 and 5-9, three to B.
  auto e = std::vector<std::pair<uint32_t, uint32_t>>{};
  for (uint32_t i = 0; i + 1 < 12; ++i) e.push_back({i, i + 1});
  e.push_back({6, 8});
  e.push_back({5, 9});
  const NeighborGraph g = from_edges(12, e);
  const Segmentation seg = labels({0, 0, 0, 0, 0, 1, 1, 2, 2, 2, 2, 2});
  const Segmentation merged = merge_small_surfaces(g, seg, 3);
  EXPECT_EQ(merged.surface, (std::vector<uint32_t>{0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1}));
  EXPECT_EQ(merged.sizes, (std::vector<uint32_t>{5, 7}));
  // min_size 1 (or 2: F has 2 splats) leaves everything.
  EXPECT_EQ(merge_small_surfaces(g, seg, 1).surface, seg.surface);
  EXPECT_EQ(merge_small_surfaces(g, seg, 2).surface, seg.surface);
}

TEST(GraphMergeSmallSurfaces, TiesGoToTheLargerNeighbourThenTheLowerId) {
  // A = {0..3}, F = {4}, B = {5..10}: one edge each way; B is larger.
  const NeighborGraph g = path(11);
  EXPECT_EQ(merge_small_surfaces(g, labels({0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2}), 2).surface,
            (std::vector<uint32_t>{0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1}));
  // Equal sizes: the lower id (A).
  const NeighborGraph h = path(9);
  EXPECT_EQ(merge_small_surfaces(h, labels({0, 0, 0, 0, 1, 2, 2, 2, 2}), 2).surface,
            (std::vector<uint32_t>{0, 0, 0, 0, 0, 1, 1, 1, 1}));
}

TEST(GraphMergeSmallSurfaces, ChainsOfFragmentsEndInALargeSurface) {
  // The path 0..7: A = {0..4}, then the singletons 5, 6, 7. Smallest first, lower id first:
  // 5 has one edge to A and one to {6}, and A is larger, so it joins A; then 6 and 7 likewise.
  const NeighborGraph g = path(8);
  const Segmentation merged = merge_small_surfaces(g, labels({0, 0, 0, 0, 0, 1, 2, 3}), 4);
  EXPECT_EQ(merged.surface, std::vector<uint32_t>(8, 0));
  EXPECT_EQ(merged.sizes, std::vector<uint32_t>{8});
}

TEST(GraphMergeSmallSurfaces, IsolatedFragmentStaysAndIdsFollowTheLowestSplat) {
  // 0-1-2 | 3 alone | 4-5-6 with {2} and {3} small: 2 joins {0, 1}; 3 has no edge and stays.
  const NeighborGraph g = from_edges(7, {{0, 1}, {1, 2}, {4, 5}, {5, 6}});
  const Segmentation merged = merge_small_surfaces(g, labels({0, 0, 1, 2, 3, 3, 3}), 2);
  EXPECT_EQ(merged.surface, (std::vector<uint32_t>{0, 0, 0, 1, 2, 2, 2}));
  EXPECT_EQ(merged.sizes, (std::vector<uint32_t>{3, 1, 3}));
}

TEST(GraphMergeSmallSurfaces, IsolatedStrayNearASurfaceJoinsIt) {
  // Splats 0-1-2 on the x axis 1 apart, radius 0.5 (touching); splat 3 lifted 1.5 above splat 2,
  // radius 0.3: no edge (1.5 > 0.5 + 0.3), but within twice the radii (1.5 < 2 (0.3 + 0.5)), so
  // it joins {0, 1, 2}. Splat 4 far away (10 above) stays on its own, as does everything without
  // the spheres.
  const NeighborGraph g = from_edges(5, {{0, 1}, {1, 2}});
  const std::vector<Vec3f> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 1.5f}, {0, 0, 10}};
  const std::vector<float> r = {0.5f, 0.5f, 0.5f, 0.3f, 0.5f};
  const Segmentation seg = labels({0, 0, 0, 1, 2});
  const Segmentation merged = merge_small_surfaces(g, seg, 2, {p, r});
  EXPECT_EQ(merged.surface, (std::vector<uint32_t>{0, 0, 0, 0, 1}));
  EXPECT_EQ(merged.sizes, (std::vector<uint32_t>{4, 1}));
  EXPECT_EQ(merge_small_surfaces(g, seg, 2).surface, seg.surface);
  // A cluster of two as far off (splats 3 and 4 touching each other): joins as one.
  const NeighborGraph h = from_edges(5, {{0, 1}, {1, 2}, {3, 4}});
  const std::vector<Vec3f> q = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 1.5f}, {2.5f, 0, 1.5f}};
  EXPECT_EQ(merge_small_surfaces(h, labels({0, 0, 0, 1, 1}), 3, {q, r}).surface,
            std::vector<uint32_t>(5, 0));
  EXPECT_THROW(merge_small_surfaces(g, seg, 2, {std::span(p).first(4), r}), std::invalid_argument);
}

TEST(GraphMergeSmallSurfaces, RejectsMismatchedInput) {
  Segmentation seg = labels({0, 0, 1});
  EXPECT_THROW(merge_small_surfaces(path(4), seg, 2), std::invalid_argument);
  seg.surface[0] = 5;
  EXPECT_THROW(merge_small_surfaces(path(3), seg, 2), std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
