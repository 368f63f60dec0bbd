// The renderer against exact references: a sphere and a torus sampled as splats, rendered beside
// a ray-traced analytic image with the same camera and shading. Asserts no holes (reference mask
// eroded by 1 px fully covered), silhouettes within 1 px, PSNR >= 30 dB inside the mask, at
// several zooms including splats 10+ px across.
#include <gtest/gtest.h>

#include <cstdio>

#include "render/frame_renderer.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

using testing::Shape;

struct Case {
  const char* name;
  Shape shape;
  int splats;
  float distance;  // from the origin, along the view direction
  BlendMode blend;
  float min_splat_px;  // the splat diameter this case must reach on screen (at the centre)
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class RenderReference : public ::testing::TestWithParam<Case> {};

TEST_P(RenderReference, MatchesRayTracedShape) {
  const Case& k = GetParam();
  Camera cam;
  cam.width = 200;
  cam.height = 160;
  cam.fov_y_deg = 40;
  cam.up = {0, 0, 1};
  const Vec3f dir = normalized(Vec3f{0.8f, -0.5f, 0.55f});
  cam.eye = dir * k.distance;
  cam.target = {0, 0, 0};

  RenderScene scene = make_render_scene(testing::sample_shape(k.shape, k.splats), "test");
  RenderOptions options;
  options.blend = k.blend;
  options.planes = {true, false, true};
  Framebuffer fb;
  FrameRenderer renderer;
  const FrameStats stats = renderer.render(scene, cam, options, fb);

  const Projection proj = make_projection(cam);
  const float splat_px = 2 * scene.mean_radius * proj.focal_px / k.distance;
  EXPECT_GE(splat_px, k.min_splat_px);
  const auto ref =
      testing::ray_trace(k.shape, cam, make_shading(ShadeMode::kPhong, proj, scene.bounds));
  const auto cmp = testing::compare(ref, fb);
  testing::dump_images(k.name, ref, fb);
  std::printf(
      "%s: splats %.1f px, mask %d px, holes %d, outside %d, PSNR %.2f dB, "
      "fragments %llu, overflowed %llu\n",
      k.name, splat_px, cmp.mask_pixels, cmp.holes, cmp.outside, cmp.psnr,
      (unsigned long long)stats.fragments, (unsigned long long)stats.pixels_overflowed);
  EXPECT_GT(cmp.mask_pixels, 2000);
  EXPECT_EQ(cmp.holes, 0);
  EXPECT_EQ(cmp.outside, 0);
  EXPECT_GE(cmp.psnr, 30.0);
}

INSTANTIATE_TEST_SUITE_P(
    Zooms, RenderReference,
    ::testing::Values(
        Case{"sphere_far", Shape::kSphere, 20000, 6.0f, BlendMode::kZThreshold, 1.5f},
        Case{"sphere_mid", Shape::kSphere, 20000, 3.0f, BlendMode::kZThreshold, 3.5f},
        Case{"sphere_near_big_splats", Shape::kSphere, 2000, 2.6f, BlendMode::kZThreshold, 10.0f},
        Case{"sphere_zrange", Shape::kSphere, 20000, 3.0f, BlendMode::kZRange, 3.5f},
        Case{"torus_far", Shape::kTorus, 30000, 7.0f, BlendMode::kZThreshold, 1.3f},
        Case{"torus_mid", Shape::kTorus, 30000, 3.5f, BlendMode::kZThreshold, 2.5f},
        Case{"torus_near_big_splats", Shape::kTorus, 6000, 2.1f, BlendMode::kZThreshold, 10.0f},
        Case{"torus_zrange", Shape::kTorus, 30000, 3.5f, BlendMode::kZRange, 2.5f}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace splatkit::render
