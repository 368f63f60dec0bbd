// The Sequential Point Tree renderer (render/select_spt.h) against the plain splat render of the
// same splats: at an error of 1 px the .spt render has no holes inside the object's mask and
// matches it (PSNR >= 30 dB inside the mask), on synthetic shapes, a coloured one and a real scan;
// as the camera recedes the number of splats drawn falls with about 1/r²; the stats.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "formats/read_cloud.h"
#include "formats/read_spt.h"
#include "render/frame_renderer.h"
#include "render/select_spt.h"
#include "render/spt_scene.h"
#include "spt/build_spt_tree.h"
#include "spt/encode_spt.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

RenderScene spt_scene_of(const SplatCloud& cloud, bool full = false) {
  spt::EncodeSptOptions o;
  o.full = full;
  const spt::SptBytes e = spt::build_spt_bytes(cloud, 1.0f, o);
  return make_spt_scene(parse_spt(e.bytes, "test.spt"), "test.spt");
}

SplatCloud real_scan() {
  LoadedCloud doc = read_cloud(std::string(SPLATKIT_SOURCE_DIR) + "/data-samples/cad.ply");
  for (Vec3f& n : doc.cloud.normals) n = normalized(n);
  doc.cloud.extras.clear();
  return std::move(doc.cloud);
}

SplatCloud two_spheres() {
  ShapeOptions o;
  o.kind = ShapeKind::kTwoSpheres;
  o.points = 20000;
  o.random = true;
  o.seed = 5;
  return make_shape(o);
}

struct Case {
  const char* name;
  int which;  // 0 sphere, 1 torus, 2 two coloured spheres, 3 the CAD scan (data-samples/cad.ply)
  float distance;
  bool full;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

SplatCloud cloud_of(int which) {
  switch (which) {
    case 0:
      return testing::sample_shape(testing::Shape::kSphere, 20000);
    case 1:
      return testing::sample_shape(testing::Shape::kTorus, 30000);
    case 2:
      return two_spheres();
    default:
      return real_scan();
  }
}

Camera camera_at(float distance, int width = 200, int height = 160) {
  Camera cam;
  cam.width = width;
  cam.height = height;
  cam.fov_y_deg = 40;
  cam.up = {0, 0, 1};
  cam.eye = normalized(Vec3f{0.8f, -0.5f, 0.55f}) * distance;
  cam.target = {0, 0, 0};
  return cam;
}

class RenderSpt : public ::testing::TestWithParam<Case> {};

TEST_P(RenderSpt, MatchesThePlainSplatRenderAtOnePixel) {
  const Case& k = GetParam();
  const SplatCloud cloud = cloud_of(k.which);
  RenderScene plain = make_render_scene(SplatCloud(cloud), "test");
  const RenderScene sp = spt_scene_of(cloud, k.full);
  const Camera cam = camera_at(k.distance);
  RenderOptions options;
  options.planes = {true, false, true};
  options.epsilon = 2 * plain.mean_radius;  // the same blending epsilon for both
  options.spt_error_px = 1;
  Framebuffer a, b;
  FrameRenderer renderer;
  renderer.render(plain, cam, options, a);
  const FrameStats s = renderer.render(sp, cam, options, b);

  const auto [pixels, holes, psnr] = testing::compare_inside_mask(a, b, cam.width, cam.height);
  std::printf(
      "%s: mask %d px, holes %d, PSNR %.2f dB, prefix %llu, culled %llu, drawn %llu of %zu\n",
      k.name, pixels, holes, psnr, (unsigned long long)s.lod.spt_prefix,
      (unsigned long long)s.lod.spt_culled, (unsigned long long)s.splats_in, sp.spt->size());
  EXPECT_GT(pixels, 2000);
  EXPECT_EQ(holes, 0);
  EXPECT_GE(psnr, 30.0);
  EXPECT_LT(s.splats_in, cloud.size());  // a level of detail, not every leaf
  EXPECT_GT(s.lod.spt_culled, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, RenderSpt,
    ::testing::Values(Case{"sphere_mid", 0, 3.0f, false}, Case{"sphere_far_full", 0, 6.0f, true},
                      Case{"torus_mid", 1, 3.5f, false}, Case{"two_spheres_colour", 2, 4.0f, false},
                      Case{"cad_scan", 3, 6.0f, false}),
    [](const ::testing::TestParamInfo<Case>& p) { return std::string(p.param.name); });

TEST(RenderSpt, DrawnCountFallsWithTheSquareOfTheDistance) {
  ShapeOptions o;
  o.kind = ShapeKind::kSphere;
  o.points = 60000;
  o.random = true;
  const RenderScene sp = spt_scene_of(make_shape(o));
  // 800 × 640, focal 879 px: a leaf (diameter ~0.03) is 1 px at distance ~26; the sphere fills
  // 29 px at distance 60. Between those the count should fall about 4× per doubling.
  std::size_t count[3];
  const float distances[3] = {30, 60, 120};
  for (int i = 0; i < 3; ++i) {
    LodStats st;
    count[i] =
        select_spt(*sp.spt, sp.bounds, make_projection(camera_at(distances[i], 800, 640)), 1, &st)
            .count;
    EXPECT_EQ(st.spt_prefix - st.spt_culled, count[i]);
  }
  std::printf("drawn at 30, 60, 120: %zu %zu %zu\n", count[0], count[1], count[2]);
  for (int i = 0; i < 2; ++i) {
    const double ratio = double(count[i]) / double(count[i + 1]);
    EXPECT_GT(ratio, 2.8) << i;
    EXPECT_LT(ratio, 5.7) << i;
  }
}

TEST(RenderSpt, LargerErrorsDrawFewerSplatsAndTheOrderIsTheSameForAnyThreadCount) {
  const RenderScene sp = spt_scene_of(testing::sample_shape(testing::Shape::kTorus, 30000));
  const Projection p = make_projection(camera_at(4.0f));
  const std::size_t n1 = select_spt(*sp.spt, sp.bounds, p, 1).count;
  const std::size_t n4 = select_spt(*sp.spt, sp.bounds, p, 4).count;
  EXPECT_GT(n1, 2 * n4);
  DrawList one, two;
  tbb::task_arena(1).execute([&] { one = select_spt(*sp.spt, sp.bounds, p, 1); });
  tbb::task_arena(2).execute([&] { two = select_spt(*sp.spt, sp.bounds, p, 1); });
  ASSERT_EQ(one.count, two.count);
  for (std::size_t i = 0; i < one.count; ++i) {
    ASSERT_EQ(one.positions[i], two.positions[i]);
    ASSERT_EQ(one.radii[i], two.radii[i]);
  }
}

// The z-buffer fast path: entries below 1 px drawn as points give exactly the keys of drawing
// each selected entry as a disc, and the buffer is the same for any thread count.
TEST(RenderSpt, ZBufferPointsMatchDiscsBelowOnePixelForAnyThreadCount) {
  const RenderScene sp = spt_scene_of(testing::sample_shape(testing::Shape::kTorus, 30000));
  const SptModel& m = *sp.spt;
  const Projection p = make_projection(camera_at(30.0f, 400, 320));
  const float error = 0.02f;
  DepthKeyBuffer a, b, ref;
  a.reset(p.width, p.height);
  b.reset(p.width, p.height);
  ref.reset(p.width, p.height);
  SptZBufferCounts ca, cb;
  tbb::task_arena(1).execute([&] { ca = draw_spt_zbuffer(m, sp.bounds, p, error, a); });
  tbb::task_arena(2).execute([&] { cb = draw_spt_zbuffer(m, sp.bounds, p, error, b); });
  EXPECT_EQ(a.keys, b.keys);
  EXPECT_EQ(ca.drawn, cb.drawn);
  // Every entry of the list tested and drawn as a disc.
  const float k = error / p.focal_px / m.header.epsilon;
  float widest = 0;
  uint64_t selected = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const float r = norm(m.positions[i] - p.eye) * k;
    if (!(m.r_min[i] <= r && r < m.r_max[i])) continue;
    ++selected;
    const Vec3f cam = p.to_camera(m.positions[i]);
    const float radius = 0.5f * m.diameters[i];
    zbuffer_splat(ref, p, cam, radius, static_cast<uint32_t>(i));
    widest = std::max(widest, 2 * p.focal_px * radius / cam.z);
  }
  EXPECT_EQ(selected, ca.selected);
  ASSERT_LT(widest, 1.0f);  // the view's precondition: every selected entry below a pixel
  EXPECT_GT(ca.drawn, 1000u);
  EXPECT_EQ(ca.points, ca.drawn);
  EXPECT_EQ(a.keys, ref.keys);
  std::printf("points drawn: %llu, widest %.2f px\n", static_cast<unsigned long long>(ca.points),
              widest);
}

}  // namespace
}  // namespace splatkit::render
