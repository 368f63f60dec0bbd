// renumber_surfaces and surface_members: ids by lowest splat, members grouped in index order.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "graph/renumber_surfaces.h"
#include "graph/surface_members.h"

namespace splatkit::graph {
namespace {

TEST(GraphRenumberSurfaces, IdsFollowTheLowestSplatWhateverTheLabels) {
  const std::vector<uint32_t> labels{7, 7, 2, 9, 2, 7};
  const Segmentation seg = renumber_surfaces(labels, 10);
  EXPECT_EQ(seg.surface, (std::vector<uint32_t>{0, 0, 1, 2, 1, 0}));
  EXPECT_EQ(seg.sizes, (std::vector<uint32_t>{3, 2, 1}));
  EXPECT_THROW(renumber_surfaces(labels, 9), std::invalid_argument);
  EXPECT_EQ(renumber_surfaces({}, 0).count(), 0u);
}

TEST(GraphSurfaceMembers, GroupsInIndexOrder) {
  const SurfaceMembers m = surface_members(std::vector<uint32_t>{2, 0, 2, 1, 0}, 4);
  EXPECT_EQ(m.start, (std::vector<uint64_t>{0, 2, 3, 5, 5}));
  EXPECT_EQ(m.members, (std::vector<uint32_t>{1, 4, 3, 0, 2}));
  EXPECT_EQ(std::vector<uint32_t>(m.of(2).begin(), m.of(2).end()), (std::vector<uint32_t>{0, 2}));
  EXPECT_TRUE(m.of(3).empty());
  EXPECT_THROW(surface_members(std::vector<uint32_t>{0, 4}, 4), std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
