// segment_surfaces: BFS over continuous edges, ids by lowest member.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace splatkit::graph
