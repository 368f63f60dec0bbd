// join_tile_surfaces: a plane cut by a tile border, each tile segmented on its own, comes back as
// one surface; two surfaces that only touch a halo with a point or two, or whose halo points
// split between surfaces, stay apart; ids in the order of each surface's first own point;
// kNoSurface kept; frames other than the first compared in file coordinates; bad ids refused.
#include "graph/join_tile_surfaces.h"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <vector>

namespace splatkit::graph {
namespace {

// One tile of a strip of points along x at y = `row`: its own points x in [lo, hi), its halo the
// points within `halo` outside that range, each with the id `id(x)` (a lambda of the point's x).
struct Tile {
  std::array<double, 3> origin{0, 0, 0};
  std::vector<Vec3f> positions;
  std::vector<uint32_t> own, surface;
  uint32_t count = 0;
};

template <class Id>
void add_row(Tile& t, int lo, int hi, int halo, float row, Id&& id) {
  for (int x = lo - halo; x < hi + halo; ++x) {
    if (x >= lo && x < hi) t.own.push_back(static_cast<uint32_t>(t.positions.size()));
    t.positions.push_back(Vec3f{static_cast<float>(x) - static_cast<float>(t.origin[0]), row, 0});
    t.surface.push_back(id(x));
  }
}

void add(TileSurfaceJoin& join, const Tile& t) {
  join.add_tile(t.origin, t.positions, t.own, t.surface, t.count);
}

TEST(GraphJoinTileSurfaces, APlaneCutByTheBorderIsOneSurface) {
  // Row 0: one plane over both tiles (id 0 in tile a, 1 in tile b, halos included). Row 1: two
  // planes meeting at x = 10, each tile giving the other's plane, in its halo, an id of its own.
  Tile a, b;
  add_row(a, 0, 10, 3, 0, [](int) { return 0u; });
  add_row(b, 10, 20, 3, 0, [](int) { return 1u; });
  add_row(a, 0, 10, 3, 1, [](int x) { return x < 10 ? 1u : 2u; });
  add_row(b, 10, 20, 3, 1, [](int x) { return x < 10 ? 2u : 0u; });
  a.count = 3;
  b.count = 3;
  TileSurfaceJoin join;
  add(join, a);
  add(join, b);
  TileJoinInfo info;
  const Segmentation s = join.finish(&info);
  ASSERT_EQ(s.surface.size(), 40u);
  // Own points in order: a's row 0, a's row 1, b's row 0, b's row 1.
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(s.surface[i], 0u) << i;       // a, row 0
    EXPECT_EQ(s.surface[20 + i], 0u) << i;  // b, row 0: the same plane
    EXPECT_EQ(s.surface[10 + i], 1u) << i;  // a, row 1
    EXPECT_EQ(s.surface[30 + i], 2u) << i;  // b, row 1: the other plane
  }
  EXPECT_EQ(s.sizes, (std::vector<uint32_t>{20, 10, 10}));
  EXPECT_EQ(info.tile_surfaces, 6u);
  EXPECT_EQ(info.halo_points, 24u);  // 3 on each side of each tile's rows
  EXPECT_EQ(info.matched, 12u);      // those inside the other tile
  // a's 0 and b's 1; a's 1 and b's 2 (b's halo over a's row 1); b's 0 and a's 2.
  EXPECT_EQ(info.joins, 3u);
}

TEST(GraphJoinTileSurfaces, AFewVotesOrASplitHaloDoNotJoin) {
  Tile a, b;
  // Row 0: each tile's halo over the other holds two points: fewer than kMinVotes.
  add_row(a, 0, 10, 2, 0, [](int) { return 0u; });
  add_row(b, 10, 20, 2, 0, [](int x) { return x < 10 ? 1u : 0u; });
  // Row 1: b's halo over a's surface 1 (eight points) lies on b's surfaces 2, 3 and 4 (3, 3, 2):
  // none holds half of them. a's halo over b's row sees a surface 2 of a's own, which joins b's.
  add_row(a, 0, 10, 8, 1, [](int x) { return x < 10 ? 1u : 2u; });
  add_row(b, 10, 20, 8, 1, [](int x) { return x < 5 ? 2u : x < 8 ? 3u : x < 10 ? 4u : 5u; });
  a.count = 3;
  b.count = 6;
  TileSurfaceJoin join;
  add(join, a);
  add(join, b);
  TileJoinInfo info;
  const Segmentation s = join.finish(&info);
  const auto own_a = [&](int row, int x) { return s.surface[10 * row + x]; };
  const auto own_b = [&](int row, int x) { return s.surface[20 + 10 * row + (x - 10)]; };
  EXPECT_NE(own_a(0, 0), own_b(0, 10));
  EXPECT_NE(own_a(1, 0), own_b(1, 10));
  EXPECT_EQ(info.joins, 1u);  // b's 5 and a's 2, which no own point carries
  EXPECT_EQ(s.count(), 4u);
}

TEST(GraphJoinTileSurfaces, NoSurfaceKeptAndFramesCompared) {
  Tile a, b;
  b.origin = {1000.0, 0, 0};  // b's positions in its own frame: the same file coordinates
  add_row(a, 0, 10, 3, 0, [](int x) { return x == 4 ? kNoSurface : 0u; });
  add_row(b, 10, 20, 3, 0, [](int) { return 0u; });
  a.count = 1;
  b.count = 1;
  TileSurfaceJoin join;
  add(join, a);
  add(join, b);
  TileJoinInfo info;
  const Segmentation s = join.finish(&info);
  EXPECT_EQ(s.surface[4], kNoSurface);
  for (int i = 0; i < 20; ++i)
    if (i != 4) EXPECT_EQ(s.surface[i], 0u) << i;
  EXPECT_EQ(s.sizes, (std::vector<uint32_t>{19}));
  EXPECT_EQ(info.matched, 6u);
}

TEST(GraphJoinTileSurfaces, BadInputIsRefused) {
  TileSurfaceJoin join;
  const std::vector<Vec3f> p = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<uint32_t> own = {0, 1};
  EXPECT_THROW(join.add_tile({0, 0, 0}, p, own, std::vector<uint32_t>{0, 1}, 1),
               std::invalid_argument);  // id 1 of 1 surface
  EXPECT_THROW(join.add_tile({0, 0, 0}, p, own, std::vector<uint32_t>{0}, 1),
               std::invalid_argument);  // sizes differ
  EXPECT_THROW(join.add_tile({0, 0, 0}, p, std::vector<uint32_t>{1, 0},
                             std::vector<uint32_t>{0, 0}, 1),
               std::invalid_argument);  // own not ascending
  const Segmentation empty = TileSurfaceJoin().finish();
  EXPECT_TRUE(empty.surface.empty());
  EXPECT_EQ(empty.count(), 0u);
}

}  // namespace
}  // namespace splatkit::graph
