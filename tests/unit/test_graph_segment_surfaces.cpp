// segment_surfaces: BFS over continuous edges, ids by lowest member.
#include <gtest/gtest.h>

#include <queue>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "graph/segment_surfaces.h"

namespace splatkit::graph {
namespace {

// Path 0-1-2-3-4 with the edge 2-3 sharp, and splat 5 alone; rows ascending, symmetric.
NeighborGraph path_graph() {
  NeighborGraph g;
  g.offsets = {0, 1, 3, 5, 7, 8, 8};
  g.neighbors = {1, 0, 2, 1, 3, 2, 4, 3};
  return g;
}

TEST(GraphSegmentSurfaces, SharpEdgesSplitRegions) {
  const NeighborGraph g = path_graph();
  const std::vector<uint8_t> flags{0, 0, 0, 0, 1, 1, 0, 0};  // 2->3 and 3->2 sharp
  const Segmentation seg = segment_surfaces(g, flags, 1);
  EXPECT_EQ(seg.surface, (std::vector<uint32_t>{0, 0, 0, 1, 1, 2}));
  EXPECT_EQ(seg.sizes, (std::vector<uint32_t>{3, 2, 1}));
  EXPECT_EQ(seg.count(), 3u);
}

TEST(GraphSegmentSurfaces, MaskSelectsTheBit) {
  const NeighborGraph g = path_graph();
  const std::vector<uint8_t> flags{0, 0, 0, 0, 2, 2, 0, 0};  // another bit: not sharp under mask 1
  const Segmentation seg = segment_surfaces(g, flags, 1);
  EXPECT_EQ(seg.surface, (std::vector<uint32_t>{0, 0, 0, 0, 0, 1}));
}

TEST(GraphSegmentSurfaces, IdsFollowLowestIndexNotVisitOrder) {
  // 0-3 and 1-2 connected: ids 0 for {0, 3}, 1 for {1, 2}.
  NeighborGraph g;
  g.offsets = {0, 1, 2, 3, 4};
  g.neighbors = {3, 2, 1, 0};
  const Segmentation seg = segment_surfaces(g, std::vector<uint8_t>(4, 0), 1);
  EXPECT_EQ(seg.surface, (std::vector<uint32_t>{0, 1, 1, 0}));
  EXPECT_THROW(segment_surfaces(g, std::vector<uint8_t>(3, 0), 1), std::invalid_argument);
  EXPECT_EQ(segment_surfaces(NeighborGraph{}, {}, 1).count(), 0u);
}

TEST(GraphSegmentSurfaces, MatchesBreadthFirstSearchOnRandomGraphs) {
  std::mt19937 rng(7);
  for (int round = 0; round < 23; ++round) {
    // The last rounds span several of the union-find's parallel chunks, with edges across them.
    const uint32_t n = round < 20 ? 1 + rng() % 300 : 60000 + rng() % 60000;
    std::vector<std::set<uint32_t>> rows(n);
    std::set<std::pair<uint32_t, uint32_t>> sharp;
    for (uint32_t e = 0; e < n; ++e) {
      const uint32_t i = rng() % n, j = rng() % n;
      if (i == j) continue;
      rows[i].insert(j);
      rows[j].insert(i);
      if (rng() % 4 == 0) sharp.insert({std::min(i, j), std::max(i, j)});
    }
    NeighborGraph g;
    g.offsets.push_back(0);
    std::vector<uint8_t> flags;
    for (uint32_t i = 0; i < n; ++i) {
      for (uint32_t j : rows[i]) {
        g.neighbors.push_back(j);
        flags.push_back(sharp.count({std::min(i, j), std::max(i, j)}) ? 1 : 0);
      }
      g.offsets.push_back(g.neighbors.size());
    }
    // Reference: BFS from the lowest unvisited index over continuous edges.
    std::vector<uint32_t> expected(n, ~0u);
    uint32_t next_id = 0;
    for (uint32_t s = 0; s < n; ++s) {
      if (expected[s] != ~0u) continue;
      std::queue<uint32_t> q;
      q.push(s);
      expected[s] = next_id;
      while (!q.empty()) {
        const uint32_t i = q.front();
        q.pop();
        for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k)
          if (!flags[k] && expected[g.neighbors[k]] == ~0u) {
            expected[g.neighbors[k]] = next_id;
            q.push(g.neighbors[k]);
          }
      }
      ++next_id;
    }
    std::vector<uint32_t> sizes(next_id, 0);
    for (uint32_t id : expected) ++sizes[id];
    // The edges between chunks are joined by threads at once: the large rounds run again, so
    // that different interleavings of the joins are all seen to give the same ids.
    for (int run = 0; run < (round < 20 ? 1 : 4); ++run) {
      const Segmentation seg = segment_surfaces(g, flags, 1);
      EXPECT_EQ(seg.surface, expected) << round << " run " << run;
      EXPECT_EQ(seg.count(), next_id);
      EXPECT_EQ(seg.sizes, sizes) << round << " run " << run;
    }
  }
}

}  // namespace
}  // namespace splatkit::graph
