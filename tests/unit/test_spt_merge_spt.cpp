// merge_spt (spt/merge_spt.h): tiles' lists give one list holding every tile's entries under one
// root, whose draws at any distance below the tiles' roots are the tiles' draws, in the same
// bytes for any order of the tiles; tiles that cannot join are refused naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "formats/read_spt.h"
#include "splatkit/common_origin.h"
#include "splatkit/error.h"
#include "splatkit/morton_order.h"
#include "splatkit/synthetic_shapes.h"
#include "spt/encode_spt.h"
#include "spt/merge_spt.h"

namespace splatkit::spt {
namespace {

// A torus cut into four tiles by the signs of x and y, each built alone.
std::vector<SptModel> torus_tiles(bool full, float epsilon = 1e-3f) {
  ShapeOptions s;
  s.kind = ShapeKind::kTorus;
  s.points = 8000;
  s.random = true;
  const SplatCloud torus = make_shape(s);
  std::vector<SptModel> tiles;
  for (int q = 0; q < 4; ++q) {
    SplatCloud tile;
    for (std::size_t i = 0; i < torus.size(); ++i) {
      const Vec3f& p = torus.positions[i];
      if ((p.x < 0) != (q & 1) || (p.y < 0) != ((q >> 1) & 1)) continue;
      tile.positions.push_back(p);
      tile.normals.push_back(torus.normals[i]);
      tile.radii.push_back(torus.radii[i]);
    }
    EncodeSptOptions o;
    o.full = full;
    o.epsilon = epsilon;
    const SptBytes b = build_spt_bytes(tile, 1.0f, o);
    tiles.push_back(parse_spt(b.bytes, "tile" + std::to_string(q) + ".spt"));
  }
  return tiles;
}

std::vector<std::string> names_of(std::size_t n) {
  std::vector<std::string> names;
  for (std::size_t q = 0; q < n; ++q) names.push_back("tile" + std::to_string(q) + ".spt");
  return names;
}

std::size_t drawn(const SptModel& m, float r) {
  std::size_t n = 0;
  for (std::size_t e = 0; e < m.size(); ++e) n += m.r_min[e] <= r && r < m.r_max[e];
  return n;
}

TEST(SptMerge, OneTileGivesItsOwnList) {
  const std::vector<SptModel> tiles = torus_tiles(false);
  const MergedSpt merged = merge_spt(std::span(tiles).first(1), names_of(1));
  const SptModel m = parse_spt(merged.bytes, "merged.spt");
  const SptModel& t = tiles[0];
  ASSERT_EQ(m.size(), t.size());
  EXPECT_EQ(merged.new_nodes, 0u);
  EXPECT_EQ(m.header.input_points, t.header.input_points);
  EXPECT_EQ(m.header.depth, t.header.depth);
  for (std::size_t e = 0; e < m.size(); ++e) {  // same order: the same scales' codes
    EXPECT_NEAR(m.r_min[e], t.r_min[e], 1e-4 * t.r_min[e]);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(m.positions[e][a], t.positions[e][a], m.header.step[a] + 1e-6f);
    EXPECT_GE(m.diameters[e], t.diameters[e]);  // grown by the new position error
  }
}

TEST(SptMerge, TilesGiveOneTreeWhoseDrawsBelowTheRootsAreTheTiles) {
  for (const bool full : {false, true}) {
    const std::vector<SptModel> tiles = torus_tiles(full);
    const MergedSpt merged = merge_spt(tiles, names_of(4));
    const SptModel m = parse_spt(merged.bytes, "merged.spt");  // checks order and checksum
    uint64_t points = 0, leaves = 0;
    float lowest_root = INFINITY;
    for (const SptModel& t : tiles) {
      points += t.header.input_points;
      leaves += t.leaves;
      lowest_root = std::min(lowest_root, t.r_min[0]);
    }
    EXPECT_EQ(m.header.input_points, points);
    EXPECT_EQ(m.leaves, leaves);
    EXPECT_GT(merged.new_nodes, 0u);
    EXPECT_EQ(drawn(m, 1e30f), 1u);  // one root
    EXPECT_EQ(drawn(m, 0.0f), leaves);
    // Below every tile's root the merged list draws what the tiles draw, at distances between
    // the stored values (re-quantised compact codes move a value by 1e-4 of it at most).
    std::vector<float> stored, rs;
    for (const SptModel& t : tiles)
      for (std::size_t e = 0; e < t.size(); ++e)
        if (t.r_min[e] > 0 && t.r_min[e] < lowest_root) stored.push_back(t.r_min[e]);
    std::sort(stored.begin(), stored.end());
    for (std::size_t k = 0; k + 1 < stored.size(); ++k)
      if (stored[k + 1] > stored[k] * 1.001f) rs.push_back(std::sqrt(stored[k] * stored[k + 1]));
    ASSERT_GT(rs.size(), 10u);
    std::size_t differ = 0;
    for (const float r : rs) {
      std::size_t want = 0;
      for (const SptModel& t : tiles) want += drawn(t, r);
      differ += drawn(m, r) != want;
    }
    EXPECT_EQ(differ, 0u) << (full ? "full" : "compact");
  }
}

// A tile of another origin (splat-tile's far tiles) is moved into the common frame.
TEST(SptMerge, TilesOfAnotherOriginJoinTheCommonFrame) {
  const std::vector<SptModel> tiles = torus_tiles(true);
  std::vector<SptModel> moved = tiles;
  moved[1].header.origin = {1000, 0, 0};
  for (Vec3f& p : moved[1].positions) p.x -= 1000;
  const SptModel a = parse_spt(merge_spt(tiles, names_of(4)).bytes, "a.spt");
  const SptModel b = parse_spt(merge_spt(moved, names_of(4)).bytes, "b.spt");
  EXPECT_EQ(b.header.origin, a.header.origin);
  ASSERT_EQ(a.size(), b.size());
  float far = 0;
  for (std::size_t e = 0; e < a.size(); ++e)
    far = std::max(far, norm(a.positions[e] - b.positions[e]));
  EXPECT_LT(far, 1e-3f);
  const std::array<double, 3> o[] = {{1, 0, 0}, {0, 5, 0}, {1, 0, 0}, {0, 5, 0}, {2, 0, 0}};
  EXPECT_EQ(common_origin(o), (std::array<double, 3>{0, 5, 0}));
}

// Tiles that are the whole cloud's Morton cells, built in the whole cloud's cube (a survey box
// from splat-tile), give the whole build's list: every tile entry where the whole list has it
// (the same position codes, the same intervals but for the second rounding of r), and above them
// one new root fitted as the whole root is.
TEST(SptMerge, TilesBuiltInTheWholeCubeGiveTheWholeList) {
  ShapeOptions s;
  s.kind = ShapeKind::kTorus;
  s.points = 8000;
  s.random = true;
  const SplatCloud torus = make_shape(s);
  const Bounds box = compute_bounds(torus.positions);
  const MortonFrame frame(box.min, box.max);
  EncodeSptOptions o;
  std::vector<SptModel> tiles;
  for (uint64_t cell = 0; cell < 8; ++cell) {  // the cube's octants (the torus lies in four)
    SplatCloud tile;
    for (std::size_t i = 0; i < torus.size(); ++i) {
      if (frame.code(torus.positions[i]) >> 60 != cell) continue;
      tile.positions.push_back(torus.positions[i]);
      tile.normals.push_back(torus.normals[i]);
      tile.radii.push_back(torus.radii[i]);
    }
    if (tile.size() == 0) continue;
    const SptBytes b = build_spt_bytes(tile, 1.0f, o, false, &box);
    tiles.push_back(parse_spt(b.bytes, "tile" + std::to_string(cell) + ".spt"));
  }
  ASSERT_EQ(tiles.size(), 4u);
  const MergedSpt merged = merge_spt(tiles, names_of(4));
  const SptModel m = parse_spt(merged.bytes, "merged.spt");
  const SptModel w = parse_spt(build_spt_bytes(torus, 1.0f, o).bytes, "whole.spt");
  EXPECT_EQ(merged.new_nodes, 1u);
  EXPECT_EQ(m.header.box_min, w.header.box_min);
  EXPECT_EQ(m.header.step, w.header.step);
  EXPECT_EQ(m.header.depth, w.header.depth);
  ASSERT_EQ(m.size(), w.size());
  // The whole list's entries by position (decoded from the same codes: equal floats).
  std::map<std::array<float, 3>, std::size_t> whole;
  for (std::size_t e = 0; e < w.size(); ++e)
    whole[{w.positions[e].x, w.positions[e].y, w.positions[e].z}] = e;
  ASSERT_EQ(whole.size(), w.size());
  ASSERT_TRUE(std::isinf(w.r_max[0]));  // the root first
  std::size_t other = 0;
  for (std::size_t a = 0; a < m.size(); ++a) {
    const auto it = whole.find({m.positions[a].x, m.positions[a].y, m.positions[a].z});
    if (it == whole.end()) {
      ++other;
      continue;
    }
    const std::size_t b = it->second;
    // The root is fitted over the tiles' decoded roots (grown by their position error): its
    // r_min, its children's r_max, within 1 %; every other r as the whole list's but for the
    // rounding on two scales.
    const bool root = std::isinf(w.r_max[b]), under_root = w.r_max[b] == w.r_min[0];
    EXPECT_NEAR(m.r_min[a], w.r_min[b], (root ? 1e-2 : 3e-4) * w.r_min[b]);
    if (root)
      EXPECT_TRUE(std::isinf(m.r_max[a]));
    else
      EXPECT_NEAR(m.r_max[a], w.r_max[b], (under_root ? 1e-2 : 3e-4) * w.r_max[b]);
    EXPECT_NEAR(m.diameters[a], w.diameters[b], 1e-3 * w.diameters[b]);
  }
  EXPECT_LE(other, 1u);  // the root, if its centre rounds to another code
}

TEST(SptMerge, SameBytesForAnyOrderOfTheTiles) {
  std::vector<SptModel> tiles = torus_tiles(false);
  const MergedSpt a = merge_spt(tiles, names_of(4));
  std::swap(tiles[0], tiles[3]);
  std::swap(tiles[1], tiles[2]);
  const MergedSpt b = merge_spt(tiles, names_of(4));
  EXPECT_EQ(a.bytes, b.bytes);
}

TEST(SptMerge, RefusesTilesThatCannotJoinNamingTheFile) {
  std::vector<SptModel> tiles = torus_tiles(false);
  std::vector<SptModel> other = torus_tiles(false, 2e-3f);
  tiles[2] = other[2];
  try {
    merge_spt(tiles, names_of(4));
    FAIL() << "merged tiles of different epsilon";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("tile2.spt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("epsilon"), std::string::npos) << e.what();
  }
  std::vector<SptModel> mixed = torus_tiles(false);
  mixed[3] = torus_tiles(true)[3];
  EXPECT_THROW(merge_spt(mixed, names_of(4)), Error);
}

}  // namespace
}  // namespace splatkit::spt
