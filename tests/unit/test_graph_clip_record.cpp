// The clip record: layout checks, plane folding and the fragment test ([IvoMSc] eqs. 4.17, 4.18).
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "graph/clip_record.h"
#include "graph/make_clip_planes.h"

namespace splatkit::graph {
namespace {

TEST(GraphClipRecord, PlaneFoldsTheSide) {
  // Partner at (0, 0, 1) facing +z. Front area: z > 1; behind area: z < 1; the plane is neither.
  const ClipPlane front = make_clip_plane({0, 0, 1}, {0, 0, 1}, kClipFront);
  const ClipPlane behind = make_clip_plane({0, 0, 1}, {0, 0, 1}, 0);
  EXPECT_TRUE(in_clip_area(front, {5, 5, 1.5f}));
  EXPECT_FALSE(in_clip_area(front, {5, 5, 0.5f}));
  EXPECT_FALSE(in_clip_area(front, {5, 5, 1}));
  EXPECT_TRUE(in_clip_area(behind, {5, 5, 0.5f}));
  EXPECT_FALSE(in_clip_area(behind, {5, 5, 1.5f}));
  EXPECT_FALSE(in_clip_area(behind, {5, 5, 1}));
}

// Two partners with front areas x > 0 and y > 0, one subset.
std::vector<ClipPlane> two_planes() {
  return {make_clip_plane({0, 0, 0}, {1, 0, 0}, kClipFront),
          make_clip_plane({0, 0, 0}, {0, 1, 0}, kClipFront)};
}

TEST(GraphClipRecord, UnionAndIntersectionOfOneSubset) {
  const auto planes = two_planes();
  const uint8_t union_flags[] = {kClipFront | kClipSubsetStart, kClipFront};
  const uint8_t inter_flags[] = {kClipFront | kClipSubsetStart | kClipSubsetIntersection,
                                 kClipFront};
  const ClipView u{planes.data(), union_flags, 2, false};
  const ClipView i{planes.data(), inter_flags, 2, false};
  const Vec3f both{1, 1, 0}, only_x{1, -1, 0}, neither{-1, -1, 0};
  EXPECT_TRUE(fragment_discarded(u, both));
  EXPECT_TRUE(fragment_discarded(u, only_x));
  EXPECT_FALSE(fragment_discarded(u, neither));
  EXPECT_TRUE(fragment_discarded(i, both));
  EXPECT_FALSE(fragment_discarded(i, only_x));
  EXPECT_FALSE(fragment_discarded(i, neither));
  EXPECT_FALSE(fragment_discarded(ClipView{}, both));  // no partners: never clipped
}

TEST(GraphClipRecord, SubsetsCombine) {
  // Two one-partner subsets: x > 0 and y > 0.
  const auto planes = two_planes();
  const uint8_t flags[] = {kClipFront | kClipSubsetStart, kClipFront | kClipSubsetStart};
  const ClipView any{planes.data(), flags, 2, false};
  const ClipView all{planes.data(), flags, 2, true};
  EXPECT_TRUE(fragment_discarded(any, {1, -1, 0}));
  EXPECT_FALSE(fragment_discarded(all, {1, -1, 0}));
  EXPECT_TRUE(fragment_discarded(all, {1, 1, 0}));
}

ClipPartnerTable small_table() {
  // Splat 0 has partners 1 and 2 (two subsets, intersection across); 1 and 2 have none.
  ClipPartnerTable t;
  t.offsets = {0, 2, 2, 2};
  t.partners = {1, 2};
  t.flags = {kClipFront | kClipSubsetStart, kClipSubsetStart};
  t.splat_flags = {kClipCombineIntersection, 0, 0};
  return t;
}

TEST(GraphClipRecord, TableToViews) {
  const ClipPartnerTable t = small_table();
  EXPECT_NO_THROW(t.check_consistent());
  const std::vector<Vec3f> pos{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vec3f> nrm{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
  const auto planes = make_clip_planes(t, pos, nrm);
  ASSERT_EQ(planes.size(), 2u);
  EXPECT_EQ(planes[0].m, (Vec3f{1, 0, 0}));  // front: x > 1
  EXPECT_EQ(planes[0].e, 1);
  EXPECT_EQ(planes[1].m, (Vec3f{0, -1, 0}));  // behind: y < 1
  EXPECT_EQ(planes[1].e, -1);
  const ClipView v0 = clip_view(t, planes, 0);
  EXPECT_EQ(v0.count, 2u);
  EXPECT_TRUE(v0.combine_intersection);
  EXPECT_TRUE(fragment_discarded(v0, {1.5f, 0.5f, 0}));   // x > 1 and y < 1
  EXPECT_FALSE(fragment_discarded(v0, {1.5f, 1.5f, 0}));  // x > 1 only
  EXPECT_EQ(clip_view(t, planes, 2).count, 0u);
  EXPECT_THROW(make_clip_planes(t, pos, {}), std::invalid_argument);
}

TEST(GraphClipRecord, ConsistencyViolations) {
  auto expect_bad = [](ClipPartnerTable t) {
    EXPECT_THROW(t.check_consistent(), std::logic_error);
  };
  ClipPartnerTable t = small_table();
  t.partners[0] = 3;  // out of range
  expect_bad(t);
  t = small_table();
  t.partners[0] = 0;  // itself
  expect_bad(t);
  t = small_table();
  t.flags[0] = kClipFront;  // row does not start a subset
  expect_bad(t);
  t = small_table();
  t.flags[1] |= 0x80;  // unknown bit
  expect_bad(t);
  t = small_table();
  t.splat_flags.pop_back();
  expect_bad(t);
  t = small_table();
  t.offsets = {0, 2, 1, 2};
  expect_bad(t);
}

}  // namespace
}  // namespace splatkit::graph
