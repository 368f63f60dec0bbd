// The terrain renderer shades each pixel from the heightmap at the texel it shows, not from the
// coarse triangles' vertices: on a tilted plane every pixel's normal is the plane's (to float
// precision, the map's border included); on a sinusoid drawn with one factor-1 tessellation per
// tile (4 triangles over several of its periods) every pixel's normal is within a small angle of
// the analytic one at the point the pixel shows (recovered from its depth). A tiny --tess-error
// draws every visible tile at full resolution (2·n² triangles for n texels a side); the default
// error draws fewer. The map's normal inside (from its 4 × 4 texels) equals the differences of
// its bilinear samples; one thread and two give the same image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include <oneapi/tbb/global_control.h>

#include "terrain/compute_ham.h"
#include "terrain/render_terrain.h"
#include "terrain/terrain_map.h"
#include "test_terrain_support.h"

namespace splatkit::terrain {
namespace {

using test::MemorySource;

using test::Terrain;

// Heights h(x, y) at texel (x, y), texels of `s` metres.
Terrain make_terrain(const std::function<double(double, double)>& h, int64_t w, int64_t ht,
                     int64_t tile, double s) {
  std::vector<float> v(std::size_t(w * ht));
  for (int64_t y = 0; y < ht; ++y)
    for (int64_t x = 0; x < w; ++x) v[std::size_t(y * w + x)] = float(h(double(x), double(y)));
  return test::make_terrain(v, w, ht, tile, s);
}

render::Camera camera_over(const Terrain& t, Vec3f eye_offset, int w, int h) {
  const render::BoundingSphere b = terrain_bounds(t.map, t.frame);
  render::Camera c;
  c.target = b.center;
  c.eye = b.center + eye_offset;
  c.up = {0, 1, 0};
  c.fov_y_deg = 40;
  c.width = w;
  c.height = h;
  return c;
}

render::Framebuffer render(const Terrain& t, const render::Camera& c, const TessSettings& tess,
                           TerrainRenderStats* stats = nullptr) {
  render::FramebufferPlanes planes;
  planes.aovs = true;
  planes.float_color = true;
  render::Framebuffer fb;
  fb.allocate(c.width, c.height, planes);
  TerrainRenderOptions o;
  o.tess = tess;
  const TerrainRenderStats s = render_terrain(t.map, t.tiles, t.frame, c, o, fb);
  if (stats) *stats = s;
  return fb;
}

double angle_deg(const Vec3f& a, const Vec3f& b) {
  return std::acos(std::clamp(double(dot(normalized(a), normalized(b))), -1.0, 1.0)) * 180 / M_PI;
}

TEST(TerrainRenderTerrain, PlaneNormalIsExactAtEveryPixel) {
  // h = 3x - 2y + 100 (metres, texels of 10 m): east slope 0.3, north slope +0.2 (rows run south).
  const Terrain t =
      make_terrain([](double x, double y) { return 3 * x - 2 * y + 100; }, 97, 81, 16, 10.0);
  const Vec3f expected = normalized(Vec3f{-0.3f, -0.2f, 1.0f});
  for (const Vec3f offset : {Vec3f{0, 0, 2500}, Vec3f{-700, -900, 600}}) {
    const render::Camera c = camera_over(t, offset, 160, 120);
    const render::Framebuffer fb = render(t, c, TessSettings{});
    std::size_t hits = 0;
    double worst = 0;
    for (std::size_t k = 0; k < fb.alpha.size(); ++k) {
      if (fb.alpha[k] == 0) continue;
      ++hits;
      const Vec3f n{fb.normal[3 * k], fb.normal[3 * k + 1], fb.normal[3 * k + 2]};
      worst = std::max(worst, double(norm(n - expected)));
    }
    EXPECT_GT(hits, 3000u);
    EXPECT_LT(worst, 1e-6) << "eye offset " << offset.x << "," << offset.y << "," << offset.z;
  }
}

TEST(TerrainRenderTerrain, SinusoidNormalPerPixelOnCoarseTriangles) {
  // h = A sin(2πx/λ) cos(2πy/λ), λ = 32 texels of 10 m, A = 40 m: slopes up to 0.79.
  const double A = 40, L = 32, s = 10, k = 2 * M_PI / L;
  const Terrain t = make_terrain(
      [&](double x, double y) { return A * std::sin(k * x) * std::cos(k * y); }, 129, 129, 32, s);
  TessSettings coarse;  // factor 1 everywhere: 4 triangles a tile, each spanning a period
  coarse.error_px = 1e9f;
  coarse.d_max_tiles = 0;
  const render::Camera c = camera_over(t, {-500, -1200, 1400}, 200, 150);
  TerrainRenderStats stats;
  const render::Framebuffer fb = render(t, c, coarse, &stats);
  ASSERT_EQ(stats.triangles, 4 * stats.visible_tiles);
  const render::Projection p = render::make_projection(c);
  std::size_t hits = 0;
  double worst = 0, sum = 0;
  for (int py = 0; py < c.height; ++py)
    for (int px = 0; px < c.width; ++px) {
      const std::size_t at = std::size_t(py) * std::size_t(c.width) + std::size_t(px);
      if (fb.alpha[at] == 0) continue;
      // The point the pixel shows, on its triangle: texel (u, v) from its depth.
      const Vec3f q = p.eye + p.ray(float(px) + 0.5f, float(py) + 0.5f) * fb.depth[at];
      const double u = double(q.x) / s, v = -double(q.y) / s;
      if (u < 1 || v < 1 || u > 127 || v > 127) continue;  // one-sided differences on the border
      const double dhdx = A * k * std::cos(k * u) * std::cos(k * v) / s;   // per metre east
      const double dhdy = -A * k * std::sin(k * u) * std::sin(k * v) / s;  // per metre south
      const Vec3f analytic{float(-dhdx), float(dhdy), 1.0f};
      const Vec3f n{fb.normal[3 * at], fb.normal[3 * at + 1], fb.normal[3 * at + 2]};
      const double e = angle_deg(n, analytic);
      worst = std::max(worst, e);
      sum += e;
      ++hits;
    }
  ASSERT_GT(hits, 10000u);
  // Central differences one texel apart: the slope times sin(k)/k = 0.9936, about 0.3° here.
  EXPECT_LT(worst, 1.0);
  EXPECT_LT(sum / double(hits), 0.5);
  std::printf("sinusoid on factor-1 tiles: %zu pixels, normal error mean %.3f°, worst %.3f°\n",
              hits, sum / double(hits), worst);
}

TEST(TerrainRenderTerrain, TinyErrorDrawsFullResolution) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 1.5);
  std::vector<double> bumps(65 * 65);
  for (double& b : bumps) b = noise(rng);
  const Terrain t = make_terrain(
      [&](double x, double y) {
        return 300 + 80 * std::sin(x / 7) * std::cos(y / 11) + bumps[std::size_t(y * 65 + x)];
      },
      65, 65, 16, 30.0);
  const render::Camera c = camera_over(t, {-1500, -2500, 2200}, 320, 200);
  TessSettings fine;
  fine.error_px = 1e-4f;
  TerrainRenderStats full, normal;
  render(t, c, fine, &full);
  render(t, c, TessSettings{}, &normal);
  EXPECT_EQ(full.visible_tiles, 16u);
  EXPECT_EQ(full.triangles, 2 * 16 * 16 * full.visible_tiles);
  EXPECT_EQ(full.histogram[16], 5 * full.visible_tiles);  // four edges and the inner factor
  EXPECT_LT(normal.triangles, full.triangles);
}

TEST(TerrainRenderTerrain, FactorStopsAtOneTexelPerSegment) {
  render::Camera c;
  c.eye = {0, 0, 0};
  c.target = {1, 0, 0};
  const render::Projection p = render::make_projection(c);
  TessSettings s;
  EXPECT_EQ(tess_factor(64, 100, {50, 0, 0}, p, 100, s, 0, 32), 32);   // T_max 64, 32 texels
  EXPECT_EQ(tess_factor(64, 100, {50, 0, 0}, p, 100, s, 0, 100), 64);  // a GPU's limit
  s.error_px = 1e-6f;                                                  // T_err ≫ n: n
  EXPECT_EQ(tess_factor(1, 100, {1e4, 0, 0}, p, 100, s, 0.5, 16), 16);
  // T_err = 16·sqrt(f·0.5·1 / (8·1000·2)), f = 360 / tan(20°) = 989.1 (720 rows, 40°), seen
  // horizontally: 2.81.
  s.error_px = 2;
  EXPECT_EQ(tess_factor(1, 1e-3, {1000, 0, 0}, p, 100, s, 0.5, 16), 3);
  EXPECT_EQ(tess_factor(1, 1e-3, {1000, 0, 0}, p, 100, s, 0.0, 16), 1);  // flat: T(d) alone
  EXPECT_EQ(tile_curvature(64), 1.0);
}

TEST(TerrainRenderTerrain, MapNormalIsTheDifferenceOfBilinearSamples) {
  const Terrain t = make_terrain(
      [](double x, double y) { return 50 * std::sin(x / 3) + 20 * std::cos(x * y / 40); }, 23, 17,
      8, 7.0);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(-0.5, 22.5), uy(-0.5, 16.5);
  for (int i = 0; i < 5000; ++i) {
    const double x = i < 4 ? double(i % 2) * 22 : ux(rng), y = i < 4 ? double(i / 2) * 16 : uy(rng);
    const double cx = std::clamp(x, 0.0, 22.0), cy = std::clamp(y, 0.0, 16.0);
    const double xa = std::max(0.0, cx - 1), xb = std::min(22.0, cx + 1);
    const double ya = std::max(0.0, cy - 1), yb = std::min(16.0, cy + 1);
    const double dx = (t.map.sample(xb, cy) - t.map.sample(xa, cy)) / (xb - xa);
    const double dy = (t.map.sample(cx, yb) - t.map.sample(cx, ya)) / (yb - ya);
    const Vec3f expected = normalized(Vec3f{float(-dx / 7), float(dy / 7), 1.0f});
    EXPECT_LT(norm(t.map.normal(x, y, 7, 7) - expected), 1e-6f) << x << "," << y;
  }
}

TEST(TerrainRenderTerrain, SameBytesOnOneThreadAndTwo) {
  const Terrain t =
      make_terrain([](double x, double y) { return 300 + 80 * std::sin(x / 7) * std::cos(y / 11); },
                   97, 81, 16, 30.0);
  const render::Camera c = camera_over(t, {-1500, -2500, 2200}, 320, 200);
  std::vector<uint8_t> images[2];
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    images[threads - 1] = render(t, c, TessSettings{}).rgb8;
  }
  EXPECT_EQ(images[0], images[1]);
}

}  // namespace
}  // namespace splatkit::terrain
