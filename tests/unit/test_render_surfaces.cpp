// Surface ids in reconstruction ([IvoMSc] §5.5, docs/references.md): two interpenetrating spheres,
// red and blue, drawn unlit, show no pixel of mixed colour along their intersection when
// reconstruction keeps surfaces apart, and a band of mixed pixels along it when it does not. Also
// the surface-id plane and the false-colour palettes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "render/frame_renderer.h"
#include "render/render_scene.h"
#include "render/splat_palette.h"
#include "test_render_graph_support.h"

namespace splatkit::render {
namespace {

struct Mixed {
  int mixed = 0, red = 0, blue = 0;
  float farthest_from_crease = 0;  // of the mixed pixels' surface points, scene units
};

Mixed count_mixed(const Framebuffer& fb, const Projection& pr) {
  Mixed m;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const std::size_t p = std::size_t(y) * fb.width + x;
      if (fb.alpha[p] == 0) continue;
      const float r = fb.rgba[4 * p], b = fb.rgba[4 * p + 2];
      m.red += r > 0.9f && b < 0.01f;
      m.blue += b > 0.9f && r < 0.01f;
      if (!(r > 0.1f && b > 0.1f)) continue;
      ++m.mixed;
      const Vec3f point = pr.eye + pr.ray(x + 0.5f, y + 0.5f) * fb.depth[p];
      m.farthest_from_crease =
          std::max(m.farthest_from_crease, distance_to_crease(ShapeKind::kTwoSpheres, point));
    }
  return m;
}

// keep_inside: false, the visible union (a crease, clipped); true, two whole spheres crossing
// (data-samples/two-spheres.ply: intersection splats, never clipped).
class RenderSurfacesTwoSpheres : public ::testing::TestWithParam<bool> {};

TEST_P(RenderSurfacesTwoSpheres, NoMixedColourAlongTheIntersection) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kTwoSpheres;
  shape.points = 30000;
  shape.keep_inside = GetParam();
  const testing::GraphScene g = testing::make_graph_scene(shape);
  ASSERT_EQ(g.stats.surfaces, 2u);
  const Camera cam = orbit_camera(g.scene.bounds, 95, 20, std::nullopt, {0, 0, 1}, 40, 320, 240);
  const Projection pr = make_projection(cam);
  RenderOptions o;
  o.shade = ShadeMode::kFlat;
  o.planes = {true, true, true, true};
  FrameRenderer r;
  auto mixed = [&](bool surface_ids, bool clip, const std::string& name) {
    o.surface_ids = surface_ids;
    o.clip = clip;
    Framebuffer fb;
    r.render(g.scene, cam, o, fb);
    testing::dump_rgb8(name + (GetParam() ? "_whole" : "_union"), fb);
    if (surface_ids) {
      // The surface-id plane: both spheres and the background, nothing else.
      std::set<uint32_t> ids(fb.surface_id.begin(), fb.surface_id.end());
      EXPECT_EQ(ids, (std::set<uint32_t>{0, 1, kNoSurfaceId}));
    }
    return count_mixed(fb, pr);
  };
  const Mixed ids_clip = mixed(true, true, "spheres_ids_clip");
  const Mixed ids_only = mixed(true, false, "spheres_ids_noclip");
  const Mixed clip_only = mixed(false, true, "spheres_noids_clip");
  const Mixed neither = mixed(false, false, "spheres_noids_noclip");
  SCOPED_TRACE(::testing::Message()
               << "mixed pixels: ids+clip " << ids_clip.mixed << ", ids " << ids_only.mixed
               << ", clip " << clip_only.mixed << ", neither " << neither.mixed << " (farthest "
               << neither.farthest_from_crease << ", splat radius " << g.scene.mean_radius << ")");
  std::printf(
      "two spheres (keep_inside %d), mixed pixels: ids+clip %d, ids %d, clip %d, neither %d\n",
      GetParam(), ids_clip.mixed, ids_only.mixed, clip_only.mixed, neither.mixed);
  EXPECT_GT(ids_clip.red, 5000);
  EXPECT_GT(ids_clip.blue, 5000);
  EXPECT_EQ(ids_clip.mixed, 0);
  EXPECT_EQ(ids_only.mixed, 0);
  // Neither: the splats overhanging the intersection blend into the other sphere, a band of
  // mixed pixels along it and only there. Clipping alone removes most of the overhang.
  EXPECT_GT(neither.mixed, 100);
  EXPECT_LT(neither.farthest_from_crease, 4 * g.scene.max_radius);
  if (!GetParam()) {
    EXPECT_LT(clip_only.mixed, neither.mixed / 2);
  }
}

INSTANTIATE_TEST_SUITE_P(UnionAndWhole, RenderSurfacesTwoSpheres, ::testing::Bool());

TEST(RenderSurfaces, PaletteIsDeterministicAndDistinct) {
  std::vector<uint32_t> ids(64);
  for (uint32_t i = 0; i < 64; ++i) ids[i] = i;
  const auto colors = surface_colors(ids);
  for (uint32_t i = 0; i < 64; ++i)
    for (uint32_t j = i + 1; j < 64; ++j) {
      // Compared as displayed (sRGB): some channel differs by at least 10 of 255.
      const Vec3f a = colors[i], b = colors[j];
      const float d = std::max({std::fabs(linear_to_srgb(a.x) - linear_to_srgb(b.x)),
                                std::fabs(linear_to_srgb(a.y) - linear_to_srgb(b.y)),
                                std::fabs(linear_to_srgb(a.z) - linear_to_srgb(b.z))});
      EXPECT_GT(d, 10.0f / 255) << i << " " << j;
    }
  const Vec3f grey = surface_color(kNoSurfaceId);
  EXPECT_EQ(grey.x, grey.y);
  EXPECT_EQ(grey.y, grey.z);
  EXPECT_EQ(surface_color(7).x, surface_colors(std::vector<uint32_t>{7})[0].x);
}

TEST(RenderSurfaces, SharpAndClippedColoursFollowTheGraph) {
  const std::vector<graph::SplatClass> classes{graph::SplatClass::kSmooth, graph::SplatClass::kEdge,
                                               graph::SplatClass::kIntersection};
  const auto c = sharp_colors(classes);
  EXPECT_GT(c[0].y, c[0].x);  // green
  EXPECT_GT(c[1].x, c[1].y);  // red
  EXPECT_EQ(c[1].x, c[2].x);
  graph::ClipPartnerTable t;
  t.offsets = {0, 1, 1};
  t.partners = {1};
  t.flags = {graph::kClipSubsetStart};
  t.splat_flags = {0, 0};
  const auto k = clipped_colors(t);
  EXPECT_GT(k[0].x, k[0].z);  // orange
  EXPECT_EQ(k[1].x, k[1].z);  // grey
}

}  // namespace
}  // namespace splatkit::render
