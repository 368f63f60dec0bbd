// merge_duplicates: first occurrence kept with its attributes, order kept, faces remapped, -0 = +0.
#include "normals/merge_duplicates.h"

#include <gtest/gtest.h>

#include <bit>
#include <map>
#include <tuple>
#include <unordered_map>

#include "splatkit/deterministic_rng.h"
#include "splatkit/morton_order.h"

namespace splatkit {
namespace {

SplatCloud cloud_with_attributes() {
  SplatCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {-0.0f, 0, 0}};
  c.colors = {{{10, 0, 0}}, {{11, 0, 0}}, {{12, 0, 0}}, {{13, 0, 0}}, {{14, 0, 0}}, {{15, 0, 0}}};
  c.extras.push_back({"intensity", ScalarType::kUInt16, {100, 101, 102, 103, 104, 105}});
  c.face_offsets = {0, 3, 6};
  c.face_indices = {0, 1, 3, 2, 4, 5};
  return c;
}

TEST(NormalsMergeDuplicates, KeepsFirstOccurrenceAndOrder) {
  SplatCloud c = cloud_with_attributes();
  MergeResult r = merge_duplicates(c, true);
  EXPECT_EQ(r.merged, 3u);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.positions[0], (Vec3f{0, 0, 0}));
  EXPECT_EQ(c.positions[1], (Vec3f{1, 0, 0}));
  EXPECT_EQ(c.positions[2], (Vec3f{2, 0, 0}));
  EXPECT_EQ(c.colors[0][0], 10);  // the first's colour, not 12 or 15
  EXPECT_EQ(c.colors[1][0], 11);
  EXPECT_EQ(c.colors[2][0], 13);
  EXPECT_EQ(c.extras[0].values.doubles(), (std::vector<double>{100, 101, 103}));
  EXPECT_EQ(r.representative, (std::vector<uint32_t>{0, 1, 0, 2, 1, 0}));
  EXPECT_NO_THROW(c.check_consistent());
}

TEST(NormalsMergeDuplicates, RemapsFaces) {
  SplatCloud c = cloud_with_attributes();
  merge_duplicates(c);
  EXPECT_EQ(c.face_indices, (std::vector<uint32_t>{0, 1, 2, 0, 1, 0}));
  EXPECT_EQ(c.face_count(), 2u);
}

// merge_sorted_duplicates after morton_sort gives what merge_duplicates before it gives.
TEST(NormalsMergeDuplicates, MergedAfterTheSortAsBeforeIt) {
  DeterministicRng rng{17};
  SplatCloud c;
  for (int i = 0; i < 90000; ++i) {
    c.positions.push_back({static_cast<float>(rng.next() % 40) * 0.25f,
                           static_cast<float>(rng.next() % 40) * 0.25f,
                           i % 7 == 0 ? -0.0f : static_cast<float>(rng.next() % 3)});
    c.colors.push_back({{static_cast<uint8_t>(i), static_cast<uint8_t>(i >> 8), 0}});
    c.radii.push_back(static_cast<float>(i));
  }
  c.extras.push_back({"intensity", ScalarType::kUInt32, std::vector<double>(90000)});
  for (std::size_t i = 0; i < c.size(); ++i) c.extras[0].values.set(i, static_cast<double>(i));
  SplatCloud before = c, after = c;
  const std::size_t merged = merge_duplicates(before).merged;
  const std::vector<uint32_t> expected_order = morton_sort(before.positions);
  std::vector<DuplicatePoint> copies;
  std::vector<uint32_t> order = morton_sort(after.positions, copies);
  EXPECT_EQ(merge_sorted_duplicates(after, order, copies), merged);
  EXPECT_GT(merged, 80000u);
  EXPECT_EQ(order, expected_order);
  EXPECT_EQ(after.positions, before.positions);
  EXPECT_EQ(after.colors, before.colors);
  EXPECT_EQ(after.radii, before.radii);
  EXPECT_EQ(after.extras[0].values.doubles(), before.extras[0].values.doubles());
  EXPECT_NO_THROW(after.check_consistent());
}

TEST(NormalsMergeDuplicates, NoDuplicatesLeavesCloudUnchanged) {
  SplatCloud c;
  c.positions = {{3, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 0, 1e-7f}};
  SplatCloud before = c;
  MergeResult r = merge_duplicates(c, true);
  EXPECT_EQ(r.merged, 0u);
  EXPECT_EQ(c.positions, before.positions);
  EXPECT_EQ(r.representative, (std::vector<uint32_t>{0, 1, 2, 3}));
}

TEST(NormalsMergeDuplicates, ManyBucketsMatchAMapOfFirstOccurrences) {
  // 60000 points over 20000 positions on a coarse grid (many copies, spread over many buckets,
  // in random order), checked against a std::map from position to first index.
  DeterministicRng rng{5};
  SplatCloud c;
  for (int i = 0; i < 60000; ++i) {
    const uint64_t cell = rng.next() % 20000;
    c.positions.push_back({static_cast<float>(cell % 40), static_cast<float>(cell / 40 % 25),
                           static_cast<float>(cell / 1000) * 0.5f});
  }
  std::map<std::tuple<float, float, float>, uint32_t> first_of;
  std::vector<uint32_t> expected(c.size());
  std::vector<Vec3f> kept;
  for (uint32_t i = 0; i < c.size(); ++i) {
    const Vec3f& p = c.positions[i];
    auto [it, inserted] = first_of.insert({{p.x, p.y, p.z}, static_cast<uint32_t>(kept.size())});
    if (inserted) kept.push_back(p);
    expected[i] = it->second;
  }
  MergeResult r = merge_duplicates(c, true);
  EXPECT_EQ(r.merged, 60000u - kept.size());
  EXPECT_EQ(c.positions, kept);
  EXPECT_EQ(r.representative, expected);
}

TEST(NormalsMergeDuplicates, MoreThanAMillionPointsFillEveryBucket) {
  // 1.5M points (over 256 per bucket at the 4096-bucket cap), a third of them copies of earlier
  // ones at random, checked against an unordered_map from position to output index.
  DeterministicRng rng{11};
  SplatCloud c;
  for (int i = 0; i < 1500000; ++i)
    if (i > 0 && rng.next() % 3 == 0)
      c.positions.push_back(c.positions[rng.next() % c.positions.size()]);
    else
      c.positions.push_back({rng.uniformf(), rng.uniformf(), rng.uniformf()});
  std::unordered_map<uint64_t, uint32_t> first_of;  // (x, y) bits -> output index; z checked
  std::vector<uint32_t> expected(c.size());
  std::vector<Vec3f> kept;
  for (uint32_t i = 0; i < c.size(); ++i) {
    const Vec3f& p = c.positions[i];
    const uint64_t key = uint64_t{std::bit_cast<uint32_t>(p.x)} << 32 | std::bit_cast<uint32_t>(p.y);
    auto [it, inserted] = first_of.insert({key, static_cast<uint32_t>(kept.size())});
    if (inserted) kept.push_back(p);
    ASSERT_EQ(kept[it->second], p) << i;  // no two distinct points share x and y here
    expected[i] = it->second;
  }
  ASSERT_GT(c.size() - kept.size(), 400000u);
  MergeResult r = merge_duplicates(c, true);
  EXPECT_EQ(r.merged, 1500000u - kept.size());
  EXPECT_EQ(c.positions, kept);
  EXPECT_EQ(r.representative, expected);
}

TEST(NormalsMergeDuplicates, AllIdenticalAndEmpty) {
  SplatCloud c;
  c.positions.assign(100, Vec3f{0.5f, -2, 7});
  c.radii.assign(100, 0.25f);
  EXPECT_EQ(merge_duplicates(c).merged, 99u);
  EXPECT_EQ(c.size(), 1u);
  EXPECT_EQ(c.radii.size(), 1u);
  SplatCloud empty;
  EXPECT_EQ(merge_duplicates(empty).merged, 0u);
  EXPECT_EQ(empty.size(), 0u);
}

}  // namespace
}  // namespace splatkit
