// fill_isolated_radii: zero radii become the lower median of the positive ones.
#include "normals/fill_isolated_radii.h"

#include <gtest/gtest.h>

#include <vector>

#include "splatkit/error.h"

namespace splatkit {
namespace {

TEST(NormalsFillIsolatedRadii, ZerosTakeTheLowerMedian) {
  std::vector<float> radii = {0.4f, 0.0f, 0.1f, 0.3f, 0.0f, 0.2f};
  EXPECT_EQ(fill_isolated_radii(radii), 2u);
  // positive: 0.1 0.2 0.3 0.4 -> lower median 0.2
  EXPECT_EQ(radii, (std::vector<float>{0.4f, 0.2f, 0.1f, 0.3f, 0.2f, 0.2f}));
}

TEST(NormalsFillIsolatedRadii, NothingToFillLeavesRadiiAlone) {
  std::vector<float> radii = {0.5f, 0.25f};
  EXPECT_EQ(fill_isolated_radii(radii), 0u);
  EXPECT_EQ(radii, (std::vector<float>{0.5f, 0.25f}));
  std::vector<float> none;
  EXPECT_EQ(fill_isolated_radii(none), 0u);
}

TEST(NormalsFillIsolatedRadii, NoPositiveRadiusIsBadInput) {
  std::vector<float> radii = {0.0f};
  try {
    fill_isolated_radii(radii);
    FAIL() << "expected Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
  }
}

}  // namespace
}  // namespace splatkit
