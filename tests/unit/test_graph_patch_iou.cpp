// patch_iou: best-match intersection over union per true patch.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "graph/patch_iou.h"

namespace splatkit::graph {
namespace {

TEST(GraphPatchIou, BestSurfacePerPatch) {
  // Patch 0 = {0, 1, 2}, patch 4 = {3, 4}; surface 5 = {0, 1}, surface 7 = {2, 3, 4}.
  const std::vector<uint32_t> truth{0, 0, 0, 4, 4}, surfaces{5, 5, 7, 7, 7};
  const auto m = patch_iou(truth, surfaces);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].patch, 0u);
  EXPECT_EQ(m[0].surface, 5u);
  EXPECT_EQ(m[0].overlap, 2u);
  EXPECT_DOUBLE_EQ(m[0].iou, 2.0 / 3.0);  // |{0,1}| / |{0,1,2}|
  EXPECT_EQ(m[1].patch, 4u);
  EXPECT_EQ(m[1].surface, 7u);
  EXPECT_EQ(m[1].surface_size, 3u);
  EXPECT_DOUBLE_EQ(m[1].iou, 2.0 / 3.0);  // |{3,4}| / |{2,3,4}|
  EXPECT_DOUBLE_EQ(fraction_recovered(m, 0.6), 1.0);
  EXPECT_DOUBLE_EQ(fraction_recovered(m, 0.7), 0.0);
}

TEST(GraphPatchIou, TiesGoToTheLowerSurfaceAndNoSurfaceNeverMatches) {
  const std::vector<uint32_t> truth{1, 1, 1, 1}, surfaces{9, 9, 2, 2};
  const auto m = patch_iou(truth, surfaces);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].surface, 2u);
  EXPECT_DOUBLE_EQ(m[0].iou, 0.5);
  const std::vector<uint32_t> none(4, 0xFFFFFFFFu);
  const auto n = patch_iou(truth, none);
  EXPECT_EQ(n[0].surface, 0xFFFFFFFFu);
  EXPECT_EQ(n[0].iou, 0.0);
  EXPECT_THROW(patch_iou(truth, std::vector<uint32_t>(3, 0)), std::invalid_argument);
  EXPECT_DOUBLE_EQ(fraction_recovered({}, 0.95), 1.0);
}

}  // namespace
}  // namespace splatkit::graph
