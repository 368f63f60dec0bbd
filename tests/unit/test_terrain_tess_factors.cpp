// Tessellation factors and tiles: for random cameras around and above real and synthetic maps,
// every edge shared by two visible tiles gets the same factor from both, and the tessellated
// tiles put the same vertices on it (no cracks); a flat map gets factor 1 everywhere; tiles
// outside the frustum get 0; a tile's triangles cover it exactly and their count is the one
// --stats reports (2·64² at factor 64).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "terrain/compute_ham.h"
#include "terrain/terrain_images.h"
#include "terrain/terrain_map.h"
#include "terrain/tess_factors.h"
#include "terrain/tessellate_tile.h"
#include "test_terrain_support.h"

namespace splatkit::terrain {
namespace {

using test::MemorySource;

using test::Terrain;

using test::make_terrain;
double height_at(const void* m, double x, double y) {
  return static_cast<const TerrainMap*>(m)->sample(x, y);
}

render::Projection random_camera(const Terrain& t, std::mt19937& rng) {
  const double wx = double(t.map.width) * t.frame.sx, wy = double(t.map.height) * t.frame.sy;
  std::uniform_real_distribution<double> u(0, 1);
  render::Camera c;
  c.eye = {float(wx * (1.6 * u(rng) - 0.3)), float(-wy * (1.6 * u(rng) - 0.3)),
           float(t.map.h_max + (50 + 2000 * u(rng)) * t.frame.sx / 30)};
  c.target = {float(wx * u(rng)), float(-wy * u(rng)), float(t.map.h_min)};
  c.fov_y_deg = float(20 + 60 * u(rng));
  c.width = 640;
  c.height = 360;
  return render::make_projection(c);
}

// Checks every shared edge of `f` and the vertices the tessellator puts on it.
void expect_no_cracks(const Terrain& t, const std::vector<TileFactors>& f, std::size_t& checked) {
  const HamTiles& h = t.tiles;
  auto edge_vertices = [&](int64_t tx, int64_t ty, bool vertical, int64_t fixed) {
    TileMesh m;
    tessellate_tile(tile_extent(h, tx, ty), f[std::size_t(ty * h.tiles_x + tx)], m);
    std::set<std::pair<double, double>> on;
    for (const auto& v : m.vertices)
      if ((vertical ? v[0] : v[1]) == double(fixed)) on.insert({v[0], v[1]});
    return on;
  };
  for (int64_t ty = 0; ty < h.tiles_y; ++ty)
    for (int64_t tx = 0; tx < h.tiles_x; ++tx) {
      const TileFactors& a = f[std::size_t(ty * h.tiles_x + tx)];
      if (!a.visible()) continue;
      if (tx + 1 < h.tiles_x && f[std::size_t(ty * h.tiles_x + tx + 1)].visible()) {
        const TileFactors& b = f[std::size_t(ty * h.tiles_x + tx + 1)];
        ASSERT_EQ(a.edge[1], b.edge[3]) << "tiles " << tx << "," << ty << " and east";
        const int64_t x = tile_extent(h, tx, ty).x1;
        EXPECT_EQ(edge_vertices(tx, ty, true, x), edge_vertices(tx + 1, ty, true, x));
        ++checked;
      }
      if (ty + 1 < h.tiles_y && f[std::size_t((ty + 1) * h.tiles_x + tx)].visible()) {
        const TileFactors& b = f[std::size_t((ty + 1) * h.tiles_x + tx)];
        ASSERT_EQ(a.edge[2], b.edge[0]) << "tiles " << tx << "," << ty << " and south";
        const int64_t y = tile_extent(h, tx, ty).y1;
        EXPECT_EQ(edge_vertices(tx, ty, false, y), edge_vertices(tx, ty + 1, false, y));
        ++checked;
      }
    }
}

std::vector<float> hills(int64_t w, int64_t h) {
  std::vector<float> v(std::size_t(w * h));
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 2);
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x)
      v[std::size_t(y * w + x)] =
          float(500 + 300 * std::sin(double(x) / 9) * std::cos(double(y) / 13) +
                200 * std::exp(-std::pow(double(x - 60), 2) / 300)) +
          noise(rng);
  return v;
}

TEST(TerrainTessFactors, SharedEdgesAgreeForRandomCamerasSyntheticMap) {
  const Terrain t = make_terrain(hills(150, 97), 150, 97, 16, 30.0);
  std::mt19937 rng(11);
  std::size_t checked = 0, distinct = 0;
  std::set<int> seen;
  for (int i = 0; i < 60; ++i) {
    const std::vector<TileFactors> f =
        tess_factors(t.tiles, t.frame, random_camera(t, rng), TessSettings{}, height_at, &t.map);
    expect_no_cracks(t, f, checked);
    for (const TileFactors& x : f)
      for (int k : x.edge) seen.insert(k);
  }
  distinct = seen.size();
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(distinct, 8u) << "the cameras must produce varied factors for the test to mean much";
}

TEST(TerrainTessFactors, SharedEdgesAgreeForRandomCamerasRealSrtm) {
  const std::string path = "/work/shared/data/dem/mt_fuji_90m.tif";
  if (FILE* f = std::fopen(path.c_str(), "rb"))
    std::fclose(f);
  else
    GTEST_SKIP() << path << " not present";
  auto src = open_image_heightmap(path);
  std::vector<float> v(std::size_t(src->info().width * src->info().height));
  src->read_rows(src->info().height, v.data());
  for (float& x : v)
    if (x == -32768) x = NAN;  // voids (NaN) are filled like the file's no-data
  const Terrain t = make_terrain(v, src->info().width, src->info().height, 64, 90.0);
  std::mt19937 rng(5);
  std::size_t checked = 0;
  for (int i = 0; i < 20; ++i)
    expect_no_cracks(
        t, tess_factors(t.tiles, t.frame, random_camera(t, rng), TessSettings{}, height_at, &t.map),
        checked);
  EXPECT_GT(checked, 500u);
}

TEST(TerrainTessFactors, FlatTerrainGetsFactorOneEverywhere) {
  const Terrain t = make_terrain(std::vector<float>(100 * 80, 250.0f), 100, 80, 16, 10.0);
  std::mt19937 rng(2);
  for (int i = 0; i < 20; ++i) {
    const auto f =
        tess_factors(t.tiles, t.frame, random_camera(t, rng), TessSettings{}, height_at, &t.map);
    for (const TileFactors& x : f) {
      if (!x.visible()) continue;
      EXPECT_EQ(x.inner, 1);
      for (int k : x.edge) EXPECT_EQ(k, 1);
    }
  }
}

TEST(TerrainTessFactors, TilesOutsideTheFrustumGetZero) {
  const Terrain t = make_terrain(hills(128, 128), 128, 128, 16, 10.0);
  render::Camera c;  // looking away from the map, then at one corner
  c.eye = {640, -640, 2000};
  c.target = {640, 5000, 2000};
  c.width = 320;
  c.height = 200;
  for (const TileFactors& x : tess_factors(t.tiles, t.frame, render::make_projection(c),
                                           TessSettings{}, height_at, &t.map)) {
    EXPECT_EQ(x.inner, 0);
    for (int k : x.edge) EXPECT_EQ(k, 0);
  }
  c.eye = {-300, 300, 900};
  c.target = {40, -40, 500};
  c.fov_y_deg = 10;
  const auto f =
      tess_factors(t.tiles, t.frame, render::make_projection(c), TessSettings{}, height_at, &t.map);
  EXPECT_TRUE(f[0].visible());
  EXPECT_FALSE(f.back().visible());
}

TEST(TerrainTessFactors, FactorFollowsDistanceAndError) {
  render::Camera c;
  c.eye = {0, 0, 0};
  c.target = {1, 0, 0};
  const render::Projection p = render::make_projection(c);
  const TessSettings s;
  EXPECT_EQ(tess_factor(64, 100, {50, 0, 0}, p, 100, s), 64);   // nearer than d_max
  EXPECT_EQ(tess_factor(64, 100, {200, 0, 0}, p, 100, s), 16);  // 64·(100/200)²
  EXPECT_EQ(tess_factor(64, 1e-3, {1e6, 0, 0}, p, 100, s), 1);  // far and tiny: T_min = 1
  EXPECT_EQ(tess_factor(1, 1e6, {10, 0, 0}, p, 100, s), 1);     // flat: T_max = 1
  EXPECT_EQ(tile_t_max(0, 10), 1.0f);
  EXPECT_EQ(tile_t_max(10, 10), 64.0f);
}

TEST(TerrainTessellateTile, TrianglesCoverTheTileAndMatchTheCount) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> factor(1, 64);
  for (int i = 0; i < 200; ++i) {
    TileFactors f;
    for (int& k : f.edge) k = factor(rng);
    f.inner = i == 0 ? 64 : factor(rng);
    if (i == 0) f.edge = {64, 64, 64, 64};
    const TileExtent e{64, 128, 192, 240};
    TileMesh m;
    tessellate_tile(e, f, m);
    EXPECT_EQ(m.triangles.size(), tile_triangle_count(f));
    if (i == 0) {
      EXPECT_EQ(m.triangles.size(), 2u * 64 * 64);
    }
    double area = 0;
    for (const auto& t : m.triangles) {
      const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const double twice = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      area += std::abs(twice) / 2;
    }
    EXPECT_NEAR(area, 64.0 * 48.0, 1e-6) << "factors " << f.edge[0] << " " << f.inner;
    // Each edge carries exactly its factor + 1 distinct vertices.
    std::set<double> north;
    for (const auto& v : m.vertices)
      if (v[1] == 192) north.insert(v[0]);
    EXPECT_EQ(north.size(), std::size_t(f.edge[0] + 1));
  }
}

}  // namespace
}  // namespace splatkit::terrain
