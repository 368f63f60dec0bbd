// surface_borders: border splats and adjacent pairs of a labelled path.
#include <gtest/gtest.h>

#include <vector>

#include "graph/surface_borders.h"

namespace splatkit::graph {
namespace {

TEST(GraphSurfaceBorders, PathOfThreeSurfaces) {
  // 0-1-2-3-4-5 labelled 7 7 3 3 3 9.
  NeighborGraph g;
  g.offsets.push_back(0);
  for (uint32_t i = 0; i < 6; ++i) {
    if (i > 0) g.neighbors.push_back(i - 1);
    if (i < 5) g.neighbors.push_back(i + 1);
    g.offsets.push_back(g.neighbors.size());
  }
  const SurfaceBorders b = surface_borders(g, std::vector<uint32_t>{7, 7, 3, 3, 3, 9});
  EXPECT_EQ(b.splats, (std::vector<uint32_t>{1, 2, 4, 5}));
  auto pair = [](uint64_t a, uint64_t c) { return a << 32 | c; };
  EXPECT_EQ(b.pairs, (std::vector<uint64_t>{pair(3, 7), pair(3, 9), pair(7, 3), pair(9, 3)}));
  // From candidates that include every border splat: the same.
  const std::vector<uint32_t> candidates{0, 1, 2, 4, 5};
  const SurfaceBorders c = surface_borders(g, std::vector<uint32_t>{7, 7, 3, 3, 3, 9}, candidates);
  EXPECT_EQ(c.splats, b.splats);
  EXPECT_EQ(c.pairs, b.pairs);
}

}  // namespace
}  // namespace splatkit::graph
