// FrameRenderer and the scene/camera layer: identical images for any thread count, bounded
// A-buffer overflow keeps the front surface, back-face culling, clear errors for clouds that
// cannot be rendered, orbit cameras that frame the model, turntable file names.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>

#include <string>

#include "render/camera.h"
#include "render/frame_renderer.h"
#include "render/render_scene.h"
#include "splatkit/error.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

using testing::Shape;

Camera test_camera(const RenderScene& scene, int w = 160, int h = 120) {
  return orbit_camera(scene.bounds, 30, 20, std::nullopt, {0, 0, 1}, 40, w, h);
}

Framebuffer render_with_threads(const RenderScene& scene, const Camera& cam, const RenderOptions& o,
                                int threads) {
  Framebuffer fb;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    FrameRenderer r;
    r.render(scene, cam, o, fb);
  });
  return fb;
}

TEST(RenderFrameRenderer, SameImageForAnyThreadCount) {
  const RenderScene scene = make_render_scene(testing::sample_shape(Shape::kTorus, 20000), "t");
  // Wide enough for many tiles so that threads really share the work.
  const Camera cam = test_camera(scene, 300, 200);
  RenderOptions o;
  o.planes = {true, true, true};
  const Framebuffer one = render_with_threads(scene, cam, o, 1);
  for (int threads : {2, 3}) {
    const Framebuffer many = render_with_threads(scene, cam, o, threads);
    EXPECT_EQ(one.rgb8, many.rgb8) << threads;
    EXPECT_EQ(one.rgba, many.rgba) << threads;
    EXPECT_EQ(one.normal, many.normal) << threads;
    EXPECT_EQ(one.alpha, many.alpha) << threads;
    // Depth: +inf compares equal to itself, so vector == works.
    EXPECT_EQ(one.depth, many.depth) << threads;
  }
}

// The renderer keeps its per-splat set-up arrays from frame to frame, uninitialised: a renderer
// that drew a larger scene and a smaller one before (arrays grown, then reused with stale
// entries beyond the frame's splats) draws each frame as a fresh renderer does.
TEST(RenderFrameRenderer, ReusedRendererDrawsAsAFreshOne) {
  const RenderScene small = make_render_scene(testing::sample_shape(Shape::kSphere, 3000), "s");
  const RenderScene large = make_render_scene(testing::sample_shape(Shape::kTorus, 30000), "t");
  RenderOptions o;
  o.planes = {true, true, true};
  FrameRenderer reused;
  for (const RenderScene* scene : {&small, &large, &small, &large, &small}) {
    const Camera cam = test_camera(*scene, 200, 150);
    Framebuffer again, fresh;
    reused.render(*scene, cam, o, again);
    FrameRenderer{}.render(*scene, cam, o, fresh);
    EXPECT_EQ(again.rgb8, fresh.rgb8);
    EXPECT_EQ(again.normal, fresh.normal);
    EXPECT_EQ(again.depth, fresh.depth);
    EXPECT_GT(std::count(fresh.alpha.begin(), fresh.alpha.end(), 1.0f), 1000);
  }
}

TEST(RenderFrameRenderer, OverflowKeepsTheNearestFragments) {
  const RenderScene scene = make_render_scene(testing::sample_shape(Shape::kSphere, 20000), "s");
  const Camera cam = test_camera(scene);
  RenderOptions o;
  o.planes = {true, false, true};
  FrameRenderer r;
  Framebuffer full, tiny;
  const FrameStats s_full = r.render(scene, cam, o, full);
  o.max_fragments = 1;
  const FrameStats s_tiny = r.render(scene, cam, o, tiny);
  EXPECT_GT(s_tiny.pixels_overflowed, s_tiny.pixels_covered / 2);
  EXPECT_EQ(s_tiny.pixels_covered, s_full.pixels_covered);
  // One slot keeps the nearest fragment: same coverage, depth within a splat of the blend.
  int compared = 0;
  for (std::size_t p = 0; p < full.alpha.size(); ++p) {
    ASSERT_EQ(full.alpha[p], tiny.alpha[p]);
    if (full.alpha[p] == 0) continue;
    EXPECT_NEAR(full.depth[p], tiny.depth[p], 2 * scene.max_radius);
    ++compared;
  }
  EXPECT_GT(compared, 3000);
}

TEST(RenderFrameRenderer, BackFaceCullingOnlyRemovesHiddenWorkOnClosedModels) {
  const RenderScene scene = make_render_scene(testing::sample_shape(Shape::kSphere, 20000), "s");
  const Camera cam = test_camera(scene);
  RenderOptions o;
  FrameRenderer r;
  Framebuffer both, culled;
  const FrameStats a = r.render(scene, cam, o, both);
  o.cull_backfaces = true;
  const FrameStats b = r.render(scene, cam, o, culled);
  EXPECT_LT(b.splats_drawn, a.splats_drawn * 0.6);
  // Only rim pixels differ, where back-facing splats graze the silhouette.
  EXPECT_NEAR(double(a.pixels_covered), double(b.pixels_covered), 10);
  int differing = 0;
  for (std::size_t i = 0; i < both.rgb8.size(); i += 3)
    differing += both.rgb8[i] != culled.rgb8[i] || both.rgb8[i + 1] != culled.rgb8[i + 1] ||
                 both.rgb8[i + 2] != culled.rgb8[i + 2];
  EXPECT_LT(differing, 0.01 * a.pixels_covered);
}

TEST(RenderFrameRenderer, EmptyViewIsAllBackground) {
  const RenderScene scene = make_render_scene(testing::sample_shape(Shape::kSphere, 2000), "s");
  Camera cam = test_camera(scene);
  cam.target = cam.eye * 2.0f;  // looking away
  RenderOptions o;
  o.background = {0, 0, 0};
  FrameRenderer r;
  Framebuffer fb;
  const FrameStats s = r.render(scene, cam, o, fb);
  EXPECT_EQ(s.splats_drawn, 0u);
  EXPECT_EQ(s.pixels_covered, 0u);
  for (uint8_t v : fb.rgb8) ASSERT_EQ(v, 0);
}

TEST(RenderScene, CloudsWithoutNormalsOrRadiiNameTheToolToRun) {
  SplatCloud c = testing::sample_shape(Shape::kSphere, 10);
  c.normals.clear();
  try {
    make_render_scene(std::move(c), "scan.ply");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("scan.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("estimate-normals"), std::string::npos);
  }
  SplatCloud d = testing::sample_shape(Shape::kSphere, 10);
  d.radii[3] = 0;
  EXPECT_THROW(make_render_scene(std::move(d), "x"), Error);
  EXPECT_THROW(make_render_scene(SplatCloud{}, "x"), Error);
}

TEST(RenderScene, ColoursBecomeLinearAndBoundsEncloseTheDiscs) {
  SplatCloud c = testing::sample_shape(Shape::kSphere, 100);
  c.colors.assign(100, {255, 0, 128});
  const RenderScene s = make_render_scene(std::move(c), "x");
  EXPECT_FLOAT_EQ(s.colors[0].x, 1.0f);
  EXPECT_FLOAT_EQ(s.colors[0].y, 0.0f);
  EXPECT_NEAR(s.colors[0].z, 0.2158605f, 1e-5);  // sRGB 128/255
  for (std::size_t i = 0; i < s.size(); ++i)
    EXPECT_LE(norm(s.positions[i] - s.bounds.center) + s.radii[i], s.bounds.radius * 1.0001f);
}

TEST(RenderCamera, OrbitCameraFramesTheBoundingSphere) {
  BoundingSphere b{{1, 2, 3}, 2};
  for (float az : {0.f, 35.f, 200.f})
    for (float el : {-30.f, 25.f, 90.f}) {
      const Camera c = orbit_camera(b, az, el, std::nullopt, {0, 0, 1}, 40, 320, 200);
      const Projection p = make_projection(c);
      EXPECT_NEAR(norm(c.target - b.center), 0, 1e-5);
      // Every point of the sphere projects inside the image.
      for (int k = 0; k < 200; ++k) {
        const float t = 0.7f * k, u = 0.3f * k;
        const Vec3f dir{std::cos(t) * std::cos(u), std::sin(t) * std::cos(u), std::sin(u)};
        const Vec3f q = p.to_camera(b.center + dir * b.radius);
        const float x = p.cx + p.focal_px * q.x / q.z, y = p.cy + p.focal_px * q.y / q.z;
        EXPECT_TRUE(x > 0 && x < 320 && y > 0 && y < 200) << az << " " << el;
      }
    }
  // Elevation 90 looks straight down +z onto the centre with an upright image.
  const Projection top = make_projection(orbit_camera(b, 0, 90, 10.0f, {0, 0, 1}, 40, 64, 64));
  EXPECT_NEAR(top.forward.z, -1, 1e-5);
  EXPECT_NEAR(norm(top.eye - Vec3f{1, 2, 13}), 0, 1e-4);
}

TEST(RenderCamera, DegenerateCamerasAreUsageErrors) {
  Camera c;
  c.target = c.eye;
  EXPECT_THROW(make_projection(c), Error);
  c = Camera{};
  c.up = c.target - c.eye;
  EXPECT_THROW(make_projection(c), Error);
  c = Camera{};
  c.fov_y_deg = 180;
  EXPECT_THROW(make_projection(c), Error);
  c = Camera{};
  const Projection p = make_projection(c);
  const Vec3f centre = p.ray(0.5f * c.width, 0.5f * c.height);
  EXPECT_NEAR(norm(centre - p.forward), 0, 1e-6);
  // The top row of the image looks up (+up), the right column right.
  EXPECT_GT(dot(p.ray(0.5f * c.width, 0), c.up), 0);
}

}  // namespace
}  // namespace splatkit::render
