// drop_small_surfaces (lib/graph): segment-surfaces --min-size on a small graph with an exact
// answer.
#include <gtest/gtest.h>

#include <algorithm>

#include "graph/build_splat_graph.h"
#include "graph/drop_small_surfaces.h"
#include "graph/segment_surfaces.h"

namespace splatkit::graph {
namespace {

// A path graph 0-1-2-3-4-5-6-7-8 whose edges 2-3, 3-4 and 5-6 are sharp: surfaces
// {0,1,2} {3} {4,5} {6,7,8}, numbered 0..3 by their lowest splat.
Segmentation path_segmentation() {
  NeighborGraph g;
  std::vector<uint8_t> flags;
  g.offsets.push_back(0);
  auto sharp = [](uint32_t a, uint32_t b) {
    const uint32_t lo = std::min(a, b), hi = std::max(a, b);
    return (lo == 2 && hi == 3) || (lo == 3 && hi == 4) || (lo == 5 && hi == 6);
  };
  for (uint32_t i = 0; i < 9; ++i) {
    for (uint32_t j : {i - 1, i + 1})
      if (j < 9) {
        g.neighbors.push_back(j);
        flags.push_back(sharp(i, j) ? kEdgeSharp : 0);
      }
    g.offsets.push_back(g.neighbors.size());
  }
  return segment_surfaces(g, flags, kEdgeSharp);
}

TEST(GraphDropSmallSurfaces, RenumbersTheKeptSurfacesInOrder) {
  const Segmentation all = path_segmentation();
  ASSERT_EQ(all.surface, (std::vector<uint32_t>{0, 0, 0, 1, 2, 2, 3, 3, 3}));
  const uint32_t x = kNoSurface;

  const Segmentation min2 = drop_small_surfaces(all, 2);
  EXPECT_EQ(min2.surface, (std::vector<uint32_t>{0, 0, 0, x, 1, 1, 2, 2, 2}));
  EXPECT_EQ(min2.sizes, (std::vector<uint32_t>{3, 2, 3}));

  const Segmentation min3 = drop_small_surfaces(all, 3);
  EXPECT_EQ(min3.surface, (std::vector<uint32_t>{0, 0, 0, x, x, x, 1, 1, 1}));
  EXPECT_EQ(min3.sizes, (std::vector<uint32_t>{3, 3}));

  const Segmentation none = drop_small_surfaces(all, 4);
  EXPECT_EQ(none.surface, std::vector<uint32_t>(9, x));
  EXPECT_TRUE(none.sizes.empty());

  // Dropping twice is dropping once with the larger size, and min_size 1 keeps everything.
  EXPECT_EQ(drop_small_surfaces(min2, 3).surface, min3.surface);
  EXPECT_EQ(drop_small_surfaces(all, 1).surface, all.surface);
}

}  // namespace
}  // namespace splatkit::graph
