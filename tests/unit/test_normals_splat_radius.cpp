// splat_radius: mean distance to the radius_k nearest neighbours, skipping self, duplicates and
// unused slots.
#include "normals/splat_radius.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace splatkit {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(NormalsSplatRadius, MeanOfFirstNeighbours) {
  std::vector<float> row = {0, 1, 4, 9, 16, 25, 36};  // distances 1..6
  EXPECT_FLOAT_EQ(splat_radius(row, 5), 3.0f);        // (1+2+3+4+5)/5
  EXPECT_FLOAT_EQ(splat_radius(row, 2), 1.5f);
}

TEST(NormalsSplatRadius, SkipsDuplicatesAndUnusedSlots) {
  std::vector<float> dup = {0, 0, 0, 4, 16, kInf};
  EXPECT_FLOAT_EQ(splat_radius(dup, 5), 3.0f);  // (2+4)/2: the zeros and +inf do not count
  std::vector<float> lone = {0, kInf, kInf};
  EXPECT_EQ(splat_radius(lone, 5), 0.0f);
  EXPECT_EQ(splat_radius(std::vector<float>{0}, 5), 0.0f);
}

}  // namespace
}  // namespace splatkit
