// tile_grid: tiles anchored at 0, halos exact against brute force; tile_halo on an even grid.
#include "splatkit/tile_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "splatkit/tile_halo.h"

namespace splatkit {
namespace {

TEST(TileGrid, TilesAreAnchoredAtZero) {
  EXPECT_EQ(tile_of(0, 0, 10), (TileKey{0, 0}));
  EXPECT_EQ(tile_of(9.999, 10, 10), (TileKey{0, 1}));
  EXPECT_EQ(tile_of(-0.001, -10, 10), (TileKey{-1, -1}));
  EXPECT_EQ(tile_of(500012.5, 4100000.0, 250), (TileKey{2000, 16400}));
  EXPECT_EQ(tile_name({-3, 12}), "tile_-3_12");
}

TEST(TileGrid, HaloTilesMatchBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-50, 50);
  const double size = 10;
  for (double halo : {0.0, 0.5, 3.0, 10.0, 17.0}) {
    for (int t = 0; t < 2000; ++t) {
      const double x = u(rng), y = u(rng);
      std::vector<TileKey> got;
      halo_tiles(x, y, size, halo, got);
      std::vector<TileKey> want;
      const TileKey own = tile_of(x, y, size);
      for (int64_t i = -8; i <= 8; ++i)
        for (int64_t j = -8; j <= 8; ++j) {
          if (i == own.i && j == own.j) continue;
          const double dx = std::max({i * size - x, 0.0, x - (i + 1) * size});
          const double dy = std::max({j * size - y, 0.0, y - (j + 1) * size});
          if (std::hypot(dx, dy) <= halo) want.push_back({i, j});
        }
      ASSERT_EQ(got, want) << "x " << x << " y " << y << " halo " << halo;
    }
  }
}

TEST(TileHalo, TwiceTheReachOfTheWidestRowOnAnEvenGrid) {
  // A plane sampled every 0.5: the halo is twice the distance from an inner point to its 64th
  // nearest (counted below on the grid), a little more where border points weigh in.
  std::vector<Vec3f> grid;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) grid.push_back({0.5f * i, 0.5f * j, 0});
  // The 64th nearest point (itself included) of a grid point far from the border, by counting.
  std::vector<double> d;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) d.push_back(0.5 * std::hypot(i, j));
  std::sort(d.begin(), d.end());
  const double halo = tile_halo(grid);
  // Points near the border (4 % lie within 3 rows of it) reach farther, and the 99th percentile
  // is one of theirs: up to 1.5 times the inner reach.
  EXPECT_GE(halo, 2 * d[kTileHaloRow - 1] - 1e-6);
  EXPECT_LE(halo, 2 * 1.5 * d[kTileHaloRow - 1]);
  EXPECT_EQ(tile_halo(std::vector<Vec3f>(10, Vec3f{0, 0, 0})), 0.0);
}

}  // namespace
}  // namespace splatkit
