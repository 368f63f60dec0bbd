// setup_splats: the pixel box of a projected disc is exact (every pixel whose ray hits the disc
// is inside, and the box is the extent of the projected rim), and the
// per-pixel depth from the linear functions equals the exact ray-plane depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "render/setup_splats.h"
#include "simd_level_test.h"

namespace splatkit::render {
namespace {

struct Disc {
  Vec3f c, n;
  float r;
};

// Exact (double) ray-disc test for the ray through the centre of pixel (i, j).
bool hits(const Projection& p, const Disc& d, int i, int j, double* depth) {
  const Vec3f dir = p.ray(i + 0.5f, j + 0.5f);
  const double nx = d.n.x, ny = d.n.y, nz = d.n.z;
  const double denom = nx * dir.x + ny * dir.y + nz * dir.z;
  if (std::fabs(denom) < 1e-12) return false;
  const Vec3f rel = d.c - p.eye;
  const double t = (nx * rel.x + ny * rel.y + nz * rel.z) / denom;
  const double hx = t * dir.x - rel.x, hy = t * dir.y - rel.y, hz = t * dir.z - rel.z;
  *depth = t;
  return t > 0 && hx * hx + hy * hy + hz * hz <= double(d.r) * d.r;
}

TEST(RenderSetupSplats, BoxIsExactAndDepthMatchesRayCast) {
  Camera cam;
  cam.eye = {0, -5, 1};
  cam.target = {0, 0, 0};
  cam.width = 96;
  cam.height = 72;
  cam.fov_y_deg = 50;
  const Projection proj = make_projection(cam);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  int checked = 0, hit_pixels = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Disc d{{1.6f * u(rng), 1.6f * u(rng), 1.2f * u(rng)},
           normalized(Vec3f{u(rng), u(rng), u(rng)}),
           0.05f + 0.4f * (u(rng) + 1) / 2};
    DrawList draws;
    draws.count = 1;
    draws.positions = &d.c;
    draws.normals = &d.n;
    draws.radii = &d.r;
    SplatRaster s;
    setup_splats(draws, proj, {}, 0, 1, &s);
    int lo_x = cam.width, hi_x = -1, lo_y = cam.height, hi_y = -1;
    for (int j = 0; j < cam.height; ++j)
      for (int i = 0; i < cam.width; ++i) {
        double depth;
        if (!hits(proj, d, i, j, &depth)) continue;
        ++hit_pixels;
        lo_x = std::min(lo_x, i), hi_x = std::max(hi_x, i);
        lo_y = std::min(lo_y, j), hi_y = std::max(hi_y, j);
        ASSERT_TRUE(s.drawn()) << "trial " << trial;
        ASSERT_GE(i, s.x0) << "trial " << trial;
        ASSERT_LE(i, s.x1) << "trial " << trial;
        ASSERT_GE(j, s.y0) << "trial " << trial;
        ASSERT_LE(j, s.y1) << "trial " << trial;
        // Depth and disc coordinates from the linear functions, as the rasteriser does.
        const float di = float(i - s.x0), dj = float(j - s.y0);
        const float l = s.l[0] * di + s.l[1] * dj + s.l[2];
        const float uu = s.u[0] * di + s.u[1] * dj + s.u[2];
        const float vv = s.v[0] * di + s.v[1] * dj + s.v[2];
        EXPECT_NEAR(s.nc / l, depth, 1e-4 * depth);
        EXPECT_LE((uu * uu + vv * vv) / (l * l), 1.0f + 1e-3f);
      }
    if (hi_x < 0) continue;
    ++checked;
    // Tight: the box is the range of pixel centres inside the projected rim's extent (sampled
    // densely here; the sampling is why one pixel of slack is allowed).
    float min_x = 1e9f, max_x = -1e9f, min_y = 1e9f, max_y = -1e9f;
    Vec3f a = normalized(cross(d.n, std::fabs(d.n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    Vec3f b = cross(d.n, a);
    for (int k = 0; k < 4096; ++k) {
      const float t = 2 * 3.14159265f * k / 4096;
      // The box takes in the ring (setup_splats.h) when the splat has one.
      const Vec3f q = proj.to_camera(d.c + (a * std::cos(t) + b * std::sin(t)) *
                                               (d.r * std::sqrt(std::max(1.0f, s.ring2))));
      const float x = proj.cx + proj.focal_px * q.x / q.z, y = proj.cy + proj.focal_px * q.y / q.z;
      min_x = std::min(min_x, x), max_x = std::max(max_x, x);
      min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    }
    auto clip = [](float v, int size) { return std::clamp(int(v), 0, size - 1); };
    EXPECT_NEAR(s.x0, clip(std::ceil(min_x - 0.5f), cam.width), 1) << "trial " << trial;
    EXPECT_NEAR(s.x1, clip(std::floor(max_x - 0.5f), cam.width), 1) << "trial " << trial;
    EXPECT_NEAR(s.y0, clip(std::ceil(min_y - 0.5f), cam.height), 1) << "trial " << trial;
    EXPECT_NEAR(s.y1, clip(std::floor(max_y - 0.5f), cam.height), 1) << "trial " << trial;
  }
  EXPECT_GT(checked, 150);
  EXPECT_GT(hit_pixels, 5000);
}

TEST(RenderSetupSplats, DiscsBehindOrCrossingTheEyeAreNotDrawn) {
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  cam.up = {0, 1, 0};
  const Projection proj = make_projection(cam);
  std::vector<Vec3f> c = {{0, 0, 6}, {0, 0, 5.05f}, {0, 0, 0}, {100, 0, 0}};
  std::vector<Vec3f> n = {{0, 0, 1}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
  std::vector<float> r = {0.1f, 0.1f, 0.1f, 0.1f};
  DrawList draws{4, c.data(), n.data(), r.data(), nullptr, nullptr};
  std::vector<SplatRaster> out(4);
  EXPECT_EQ(setup_splats(draws, proj, {}, 0, 4, out.data()), 1u);
  EXPECT_FALSE(out[0].drawn());  // behind the eye
  EXPECT_FALSE(out[1].drawn());  // edge-on through the eye's depth plane
  EXPECT_TRUE(out[2].drawn());
  EXPECT_FALSE(out[3].drawn());  // outside the image
  // Back-face culling drops the disc at the origin only when its normal faces away.
  n[2] = {0, 0, -1};
  EXPECT_EQ(setup_splats(draws, proj, {true}, 0, 4, out.data()), 0u);
}

// setup_splats' vector paths (setup_splats.cpp: the baseline loop and its AVX2 compilation) give
// the portable path's bytes, for circles and ellipses, on discs in front of the camera, crossing
// the near plane, behind the eye, edge-on and off screen, with and without back-face culling.
class RenderSetupSplatsAt : public SimdLevelTest {};

TEST_P(RenderSetupSplatsAt, SameBytesAsThePortablePath) {
  Camera cam;
  cam.eye = {0.4f, -6, 1.5f};
  cam.width = 640;
  cam.height = 360;
  const Projection proj = make_projection(cam);
  const std::size_t count = 1000;  // not a multiple of the 64-splat blocks
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Vec3f> c(count), n(count), axes(count);
  std::vector<float> r(count), minor(count);
  for (std::size_t i = 0; i < count; ++i) {
    c[i] = Vec3f{u(rng) * 4, u(rng) * 8, u(rng) * 3};
    n[i] = normalized(Vec3f{u(rng), u(rng), u(rng)});
    if (i % 17 == 0) n[i] = normalized(Vec3f{0, -6, 0} - c[i]);  // facing the eye, or away
    const Vec3f any = std::fabs(n[i].x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
    axes[i] = normalized(cross(n[i], any));
    r[i] = 0.01f + 0.2f * std::fabs(u(rng));
    minor[i] = r[i] * (0.125f + 0.875f * std::fabs(u(rng)));
  }
  for (bool ellipses : {false, true}) {
    DrawList draws{count, c.data(), n.data(), r.data(), nullptr, nullptr};
    if (ellipses) {
      draws.axes = axes.data();
      draws.minor_radii = minor.data();
    }
    for (bool cull : {false, true}) {
      std::vector<SplatRaster> want(count), got(count);
      std::size_t drawn_want;
      {
        ScopedSimdLevel portable(SimdLevel::kPortable);
        drawn_want = setup_splats(draws, proj, {cull}, 0, count, want.data());
      }
      EXPECT_EQ(setup_splats(draws, proj, {cull}, 0, count, got.data()), drawn_want);
      EXPECT_GT(drawn_want, count / 10);
      for (std::size_t i = 0; i < count; ++i)
        ASSERT_EQ(std::memcmp(&want[i], &got[i], sizeof(SplatRaster)), 0)
            << "splat " << i << (ellipses ? " (ellipses)" : " (circles)") << " cull " << cull;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Simd, RenderSetupSplatsAt, kEverySimdLevel, simd_level_param_name);

}  // namespace
}  // namespace splatkit::render
