// Rendering with clip partners ([IvoMSc] §4.4, docs/references.md): a cube's and the CAD part's
// creases come out as sharp as a mesh render, at the right place, with no holes, and the faces
// meeting at a corner each keep their own pixels; without clipping the splats overhang the creases
// by about a splat radius. Shapes from make_shape (true normals, radii from the 5-neighbour
// spacing), the graph from build_splat_graph, surface ids on in both renders so that only clipping
// differs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "graph/clip_record.h"
#include "render/frame_renderer.h"
#include "splatkit/error.h"
#include "test_render_graph_support.h"

namespace splatkit::render {
namespace {

using testing::GraphScene;

Framebuffer render(const GraphScene& g, const Camera& cam, bool clip, FrameStats* stats = nullptr,
                   ShadeMode shade = ShadeMode::kNormals) {
  RenderOptions o;
  o.shade = shade;
  o.clip = clip;
  o.planes = {true, false, true, true};
  FrameRenderer r;
  Framebuffer fb;
  const FrameStats s = r.render(g.scene, cam, o, fb);
  if (stats) *stats = s;
  return fb;
}

const GraphScene& cube() {
  static const GraphScene g = [] {
    ShapeOptions o;
    o.kind = ShapeKind::kCube;
    o.points = 8000;
    return testing::make_graph_scene(o);
  }();
  return g;
}

// Three faces visible, the corner (1, 1, 1) towards the camera, no edge parallel to the pixel
// grid.
Camera cube_camera() {
  return orbit_camera(cube().scene.bounds, 30, 28, std::nullopt, {0, 0, 1}, 40, 320, 240);
}

struct CubeEdge {
  Vec3f p0, p1, n_a, n_b;
};
// The three creases from the front corner, each between faces a and b.
const CubeEdge kFrontEdges[] = {
    {{1, 1, 1}, {1, 1, -1}, {1, 0, 0}, {0, 1, 0}},
    {{1, 1, 1}, {1, -1, 1}, {1, 0, 0}, {0, 0, 1}},
    {{1, 1, 1}, {-1, 1, 1}, {0, 1, 0}, {0, 0, 1}},
};

// One edge's profiles with clipping (sharp) and without (soft): with, the 10-90 % transition
// is at most 1.5 px wide, centred on the projected edge within 0.5 px, with no background
// (holes); without, it is at least half a splat radius wide.
void expect_sharp_only_with_clipping(const char* shape, const testing::EdgeProfile& sharp,
                                     const testing::EdgeProfile& soft, float radius_px) {
  std::printf(
      "%s edge: clipped 10-90 %% width %.2f px (centre %+.2f), unclipped %.2f px; "
      "splat radius %.2f px\n",
      shape, sharp.width_10_90, sharp.centre, soft.width_10_90, radius_px);
  ASSERT_GT(sharp.samples, 50);
  EXPECT_LE(sharp.width_10_90, 1.5);
  EXPECT_LE(std::fabs(sharp.centre), 0.5);
  EXPECT_EQ(sharp.background, 0);
  EXPECT_GE(soft.width_10_90, 0.5 * radius_px);
}

TEST(RenderClip, CubeHasClipPartnersAlongItsTwelveEdges) {
  const GraphScene& g = cube();
  EXPECT_EQ(g.stats.surfaces, 6u);
  EXPECT_GT(g.scene.clip.clipped_splats(), 500u);
  // Every clipped splat lies near a crease: clipping is about edges, nothing else.
  for (std::size_t i = 0; i < g.scene.size(); ++i)
    if (g.scene.clip.offsets[i + 1] != g.scene.clip.offsets[i]) {
      ASSERT_LT(distance_to_crease(ShapeKind::kCube, g.scene.positions[i]), 2 * g.scene.radii[i])
          << i;
    }
}

TEST(RenderClip, CubeEdgesAreSharpOnlyWithClipping) {
  const GraphScene& g = cube();
  const Camera cam = cube_camera();
  const Projection pr = make_projection(cam);
  FrameStats with_stats, without_stats;
  const Framebuffer clipped = render(g, cam, true, &with_stats);
  const Framebuffer plain = render(g, cam, false, &without_stats);
  testing::dump_rgb8("cube_clip", clipped);
  testing::dump_rgb8("cube_noclip", plain);
  EXPECT_GT(with_stats.fragments_clipped, 1000u);
  EXPECT_EQ(without_stats.fragments_clipped, 0u);
  // Projected splat radius near the corner, pixels.
  const float radius_px = pr.focal_px * g.scene.mean_radius / testing::project(pr, {1, 1, 1}).z;
  ASSERT_GT(radius_px, 2.0f);
  for (const auto& e : kFrontEdges) {
    const auto sharp = testing::edge_profile(clipped, pr, e.p0, e.p1, e.n_a, e.n_b, -e.n_b);
    const auto soft = testing::edge_profile(plain, pr, e.p0, e.p1, e.n_a, e.n_b, -e.n_b);
    SCOPED_TRACE(::testing::Message()
                 << "edge to " << e.p1.x << "," << e.p1.y << "," << e.p1.z << " radius "
                 << radius_px << " px: clipped width " << sharp.width_10_90 << " centre "
                 << sharp.centre << ", unclipped width " << soft.width_10_90 << " centre "
                 << soft.centre);
    ASSERT_NO_FATAL_FAILURE(expect_sharp_only_with_clipping("cube", sharp, soft, radius_px));
  }
}

TEST(RenderClip, CubePixelsShowTheRightFaceUpToTheCorner) {
  const GraphScene& g = cube();
  const Camera cam = cube_camera();
  const auto ref = testing::reference_patches(g.shape, cam);
  const auto with = testing::rendered_patches(g, render(g, cam, true));
  const auto without = testing::rendered_patches(g, render(g, cam, false));
  const auto e_with = testing::compare_patches(ref, with, cam.width, cam.height);
  const auto e_without = testing::compare_patches(ref, without, cam.width, cam.height);
  SCOPED_TRACE(::testing::Message()
               << "clipped: wrong " << e_with.wrong << " holes " << e_with.holes << " outside "
               << e_with.outside << "; unclipped: wrong " << e_without.wrong << " holes "
               << e_without.holes << " outside " << e_without.outside << " of " << e_with.compared);
  std::printf(
      "cube pixels (of %d): clipped wrong %d holes %d outside %d; unclipped wrong %d "
      "holes %d outside %d\n",
      e_with.compared, e_with.wrong, e_with.holes, e_with.outside, e_without.wrong, e_without.holes,
      e_without.outside);
  EXPECT_EQ(e_with.holes, 0);
  EXPECT_LE(e_with.wrong, 5);
  EXPECT_LE(e_with.outside, 5);
  EXPECT_GT(e_without.wrong + e_without.outside, 10 * (e_with.wrong + e_with.outside) + 100);
  // The corner: every pixel within 4 px of its projection is drawn and shows its true face.
  const Projection pr = make_projection(cam);
  const Vec3f c = testing::project(pr, {1, 1, 1});
  int near_corner = 0;
  for (int y = int(c.y) - 4; y <= int(c.y) + 4; ++y)
    for (int x = int(c.x) - 4; x <= int(c.x) + 4; ++x) {
      if (std::hypot(x + 0.5 - c.x, y + 0.5 - c.y) > 4) continue;
      const std::size_t p = std::size_t(y) * cam.width + x;
      ASSERT_NE(with[p], testing::kNoPatch) << x << "," << y;
      // Pixel centres within half a pixel of an edge may go either way.
      bool near_edge = false;
      for (const auto& e : kFrontEdges) {
        const Vec3f a = testing::project(pr, e.p0), b = testing::project(pr, e.p1);
        const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
        near_edge =
            near_edge || std::fabs((x + 0.5 - a.x) * ey - (y + 0.5 - a.y) * ex) / len < 0.75;
      }
      if (!near_edge) {
        EXPECT_EQ(with[p], ref[p]) << x << "," << y;
      }
      ++near_corner;
    }
  EXPECT_GT(near_corner, 40);
}

TEST(RenderClip, CadPartCreasesHaveNoOverhangAndNoHoles) {
  ShapeOptions o;
  o.kind = ShapeKind::kCadPart;
  o.points = 30000;
  const GraphScene g = testing::make_graph_scene(o);
  for (const auto& [az, el] : {std::pair{35.0f, 30.0f}, std::pair{215.0f, 40.0f}}) {
    // Close enough that a splat covers several pixels (the part fills the image).
    const Camera cam =
        orbit_camera(g.scene.bounds, az, el, 1.8f * g.scene.bounds.radius, {0, 0, 1}, 40, 320, 240);
    const auto ref = testing::reference_patches(g.shape, cam);
    const Framebuffer clipped = render(g, cam, true, nullptr, ShadeMode::kPhong);
    testing::dump_rgb8("cad_clip_" + std::to_string(int(az)), clipped);
    testing::dump_rgb8("cad_noclip_" + std::to_string(int(az)),
                       render(g, cam, false, nullptr, ShadeMode::kPhong));
    const auto e_with =
        testing::compare_patches(ref, testing::rendered_patches(g, clipped), 320, 240);
    const auto e_without = testing::compare_patches(
        ref, testing::rendered_patches(g, render(g, cam, false)), 320, 240);
    SCOPED_TRACE(::testing::Message()
                 << "view " << az << "," << el << " clipped: wrong " << e_with.wrong << " holes "
                 << e_with.holes << " outside " << e_with.outside << "; unclipped: wrong "
                 << e_without.wrong << " holes " << e_without.holes << " outside "
                 << e_without.outside << " of " << e_with.compared);
    std::printf(
        "cad view %g,%g pixels (of %d): clipped wrong %d holes %d outside %d; unclipped "
        "wrong %d holes %d outside %d\n",
        az, el, e_with.compared, e_with.wrong, e_with.holes, e_with.outside, e_without.wrong,
        e_without.holes, e_without.outside);
    EXPECT_EQ(e_with.holes, 0);
    EXPECT_LE(e_with.wrong + e_with.outside, e_with.compared / 1000);
    EXPECT_GT(e_without.wrong + e_without.outside, 5 * (e_with.wrong + e_with.outside) + 100);
  }
}

// Straight creases of the CAD part seen from azimuth 35°, elevation 30° (data-samples/README.md):
// top/back (90°), top/bevel (120°), bevel/back (90°), each with a direction into face a.
struct CadEdge {
  Vec3f p0, p1, n_a, n_b, into_a;
};
const float kBevelTop = 1.5f - 1.2f / std::sqrt(3.0f);
const Vec3f kBevelNormal{std::sqrt(3.0f) / 2, 0, 0.5f};
const CadEdge kCadEdges[] = {
    {{-1.5f, 1, 1.2f}, {kBevelTop, 1, 1.2f}, {0, 0, 1}, {0, 1, 0}, {0, -1, 0}},
    {{kBevelTop, -1, 1.2f}, {kBevelTop, 1, 1.2f}, {0, 0, 1}, kBevelNormal, {-1, 0, 0}},
    {{1.5f, 1, 0}, {kBevelTop, 1, 1.2f}, kBevelNormal, {0, 1, 0}, {0, -1, 0}},
};

TEST(RenderClip, CadPartEdgesAreSharpOnlyWithClipping) {
  ShapeOptions o;
  o.kind = ShapeKind::kCadPart;
  o.points = 30000;
  const GraphScene g = testing::make_graph_scene(o);
  const Camera cam = orbit_camera(g.scene.bounds, 35, 30, std::nullopt, {0, 0, 1}, 40, 480, 360);
  const Projection pr = make_projection(cam);
  const Framebuffer clipped = render(g, cam, true), plain = render(g, cam, false);
  for (const auto& e : kCadEdges) {
    const float radius_px =
        pr.focal_px * g.scene.mean_radius / testing::project(pr, (e.p0 + e.p1) * 0.5f).z;
    const auto sharp = testing::edge_profile(clipped, pr, e.p0, e.p1, e.n_a, e.n_b, e.into_a);
    const auto soft = testing::edge_profile(plain, pr, e.p0, e.p1, e.n_a, e.n_b, e.into_a);
    ASSERT_NO_FATAL_FAILURE(expect_sharp_only_with_clipping("cad", sharp, soft, radius_px));
  }
}

TEST(RenderClip, NoClipDataRendersTheSameAsClippingOff) {
  const GraphScene& g = cube();
  const Camera cam = cube_camera();
  RenderScene bare = g.scene;
  bare.clip = {};
  bare.clip_planes.clear();
  RenderOptions o;
  o.planes = {true, false, true, true};
  FrameRenderer r;
  Framebuffer a, b;
  r.render(bare, cam, o, a);
  o.clip = false;
  r.render(g.scene, cam, o, b);
  EXPECT_EQ(a.rgb8, b.rgb8);
  EXPECT_EQ(a.depth, b.depth);
}

TEST(RenderClip, AttachRejectsATableForAnotherCloud) {
  RenderScene scene = cube().scene;
  graph::ClipPartnerTable t;
  t.offsets.assign(4, 0);
  t.splat_flags.assign(3, 0);
  EXPECT_THROW(attach_clip_partners(scene, t, "x.splk"), Error);
}

}  // namespace
}  // namespace splatkit::render
