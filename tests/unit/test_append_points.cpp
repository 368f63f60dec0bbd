// append_points: every field carried, frames converted, differing fields refused.
#include "splatkit/append_points.h"

#include <gtest/gtest.h>

#include "splatkit/error.h"

namespace splatkit {
namespace {

SplatCloud three_points() {
  SplatCloud c;
  c.origin = {500000, 4100000, 0};
  c.positions = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  c.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  c.radii = {0.1f, 0.2f, 0.3f};
  c.colors = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}};
  c.extras.emplace_back("intensity", ScalarType::kUInt16, std::vector<double>{10, 20, 30});
  return c;
}

TEST(AppendPoints, CarriesEveryFieldInTheGivenOrder) {
  const SplatCloud src = three_points();
  SplatCloud dst;
  dst.origin = src.origin;
  const std::vector<uint32_t> pick{2, 0};
  append_points(dst, src, pick, "a");
  append_points(dst, src, std::vector<uint32_t>{1}, "b");
  ASSERT_EQ(dst.size(), 3u);
  dst.check_consistent();
  EXPECT_EQ(dst.positions[0], src.positions[2]);
  EXPECT_EQ(dst.positions[2], src.positions[1]);
  EXPECT_EQ(dst.normals[1], src.normals[0]);
  EXPECT_EQ(dst.radii[0], 0.3f);
  EXPECT_EQ(dst.colors[2], src.colors[1]);
  ASSERT_EQ(dst.extras.size(), 1u);
  EXPECT_EQ(dst.extras[0].name, "intensity");
  EXPECT_EQ(dst.extras[0].type(), ScalarType::kUInt16);
  EXPECT_EQ(dst.extras[0].values[0], 30);
  EXPECT_EQ(dst.extras[0].values[2], 20);
}

TEST(AppendPoints, MovesPositionsIntoTheTargetFrame) {
  const SplatCloud src = three_points();
  SplatCloud dst;
  dst.origin = {499000, 4101000, 0};
  append_points(dst, src, std::vector<uint32_t>{0}, "a");
  EXPECT_EQ(dst.origin[0], 499000);  // kept
  EXPECT_EQ(dst.positions[0], (Vec3f{1001, -998, 3}));
}

TEST(AppendPoints, RefusesOtherFieldsAndLeavesTheTargetAsItWas) {
  const SplatCloud src = three_points();
  SplatCloud dst;
  dst.origin = src.origin;
  append_points(dst, src, std::vector<uint32_t>{0}, "a");
  SplatCloud plain = src;
  plain.normals.clear();
  try {
    append_points(dst, plain, std::vector<uint32_t>{0}, "b.laz");
    FAIL() << "accepted a cloud without normals";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_STREQ(e.what(), "b.laz: has no normals, the earlier inputs do");
  }
  EXPECT_EQ(dst.size(), 1u);
  SplatCloud retyped = src;
  retyped.extras[0] = ExtraAttribute("intensity", ScalarType::kFloat32, {1, 2, 3});
  EXPECT_NE(fields_difference(dst, retyped).find("as float32"), std::string::npos)
      << fields_difference(dst, retyped);
  SplatCloud renamed = src;
  renamed.extras[0].name = "gps_time";
  EXPECT_NE(fields_difference(dst, renamed), "");
  EXPECT_EQ(fields_difference(dst, src), "");
}

}  // namespace
}  // namespace splatkit
