// merge_qsplat_tree (qsplat/merge_qsplat.h): tiles' .qs trees give one tree holding every tile's
// leaves once, near their decoded discs in the tiles, with every decoded child inside its decoded
// parent; the same bytes for any thread count; tiles that cannot join are refused naming the file.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <string>
#include <vector>

#include "formats/read_qsplat.h"
#include "qsplat/build_qsplat_tree.h"
#include "qsplat/encode_qsplat.h"
#include "qsplat/merge_qsplat.h"
#include "splatkit/error.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::qsplat {
namespace {

// A CAD part cut into four tiles by the signs of x and y, each built alone.
std::vector<QSplatModel> part_tiles(bool color) {
  ShapeOptions s;
  s.kind = ShapeKind::kCadPart;
  s.points = 8000;
  s.random = true;
  const SplatCloud part = make_shape(s);
  Vec3f mid{0, 0, 0};
  for (const Vec3f& p : part.positions) mid += p * (1.0f / static_cast<float>(part.size()));
  std::vector<QSplatModel> tiles;
  for (int q = 0; q < 4; ++q) {
    QSplatLeaves l;
    for (std::size_t i = 0; i < part.size(); ++i) {
      const Vec3f& p = part.positions[i];
      if ((p.x < mid.x) != (q & 1) || (p.y < mid.y) != ((q >> 1) & 1)) continue;
      l.positions.push_back(p);
      l.normals.push_back(part.normals[i]);
      l.radii.push_back(part.radii[i]);
      if (color) l.colors.push_back({static_cast<uint8_t>(i), 100, static_cast<uint8_t>(q * 60)});
    }
    QSplatTree t = build_qsplat_tree(l);
    const EncodedQSplat e = encode_qsplat(t, "");
    tiles.push_back(parse_qsplat(e.bytes, "tile" + std::to_string(q) + ".qs"));
  }
  return tiles;
}

std::vector<std::string> names_of(std::size_t n) {
  std::vector<std::string> names;
  for (std::size_t q = 0; q < n; ++q) names.push_back("tile" + std::to_string(q) + ".qs");
  return names;
}

std::vector<unsigned char> merged_bytes(const std::vector<QSplatModel>& tiles) {
  MergedQSplatTree m = merge_qsplat_tree(tiles, names_of(tiles.size()));
  return encode_qsplat(m.tree, "").bytes;
}

TEST(QSplatMerge, TilesGiveOneTreeWithEveryLeafInsideItsParents) {
  const std::vector<QSplatModel> tiles = part_tiles(true);
  MergedQSplatTree merged = merge_qsplat_tree(tiles, names_of(4));
  uint64_t leaves = 0;
  for (const QSplatModel& t : tiles) leaves += t.leaves;
  EXPECT_EQ(merged.leaves, leaves);
  EXPECT_GE(merged.upper_nodes, 1u);
  const EncodedQSplat e = encode_qsplat(merged.tree, "");
  // Quantised again against the tiles' decoded discs: the leaves keep their size on average.
  EXPECT_GE(e.leaf_growth_mean, 0.95);
  EXPECT_LE(e.leaf_growth_mean, 1.1);
  const QSplatModel m = parse_qsplat(e.bytes, "merged.qs");
  EXPECT_EQ(m.leaves, leaves);
  EXPECT_TRUE(m.has_color);
  std::size_t outside = 0;
  for (std::size_t i = 0; i < m.size(); ++i)
    for (uint32_t k = 0; k < m.child_count[i]; ++k) {
      const uint32_t c = m.first_child[i] + k;
      const double d = std::sqrt(double(squared_norm(m.centres[c] - m.centres[i])));
      outside += d + m.radii[c] > m.radii[i] * (1 + 1e-5);
    }
  EXPECT_EQ(outside, 0u);
  EXPECT_GT(m.levels, tiles[0].levels);  // the tiles' trees hang below new levels
}

TEST(QSplatMerge, OneTileKeepsItsShape) {
  const std::vector<QSplatModel> tiles = part_tiles(false);
  const QSplatModel m = parse_qsplat(merged_bytes({tiles[1]}), "merged.qs");
  EXPECT_EQ(m.size(), tiles[1].size());
  EXPECT_EQ(m.levels, tiles[1].levels);
  EXPECT_EQ(m.child_count, tiles[1].child_count);
}

TEST(QSplatMerge, SameBytesForAnyThreadCount) {
  const std::vector<QSplatModel> tiles = part_tiles(true);
  std::vector<unsigned char> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = merged_bytes(tiles);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    two = merged_bytes(tiles);
  }
  EXPECT_EQ(one, two);
}

TEST(QSplatMerge, RefusesTilesOfAnotherColourOptionNamingTheFile) {
  std::vector<QSplatModel> tiles = part_tiles(true);
  tiles[3] = part_tiles(false)[3];
  try {
    merge_qsplat_tree(tiles, names_of(4));
    FAIL() << "merged tiles with and without colour";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("tile3.qs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace splatkit::qsplat
