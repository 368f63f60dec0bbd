// The QSplat traversal (render/select_qsplat.h) against the plain splat render of the same
// splats: at a 1 px threshold the .qs render leaves at most 0.2 % of the object's mask bare
// (single pixels where one leaf alone covers the surface and the cell grid moved its disc:
// leaves take the cell nearest their disc, not one that contains it, qsplat_codes.h) and matches
// it (PSNR >= 30 dB inside the mask);
// larger thresholds draw fewer, larger splats; culling counts.
// The traversal culls back faces by the nodes' normal cones, so the plain render it is compared
// with culls them too: without, the back faces' splats that stick out past a silhouette (a few
// pixels along the CAD part's edges) would count against the .qs render.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "formats/read_qsplat.h"
#include "normals/estimate_normals.h"
#include "qsplat/build_qsplat_tree.h"
#include "qsplat/encode_qsplat.h"
#include "qsplat/make_qsplat_leaves.h"
#include "render/frame_renderer.h"
#include "render/qsplat_scene.h"
#include "render/select_qsplat.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

using testing::Shape;

RenderScene qsplat_scene_of(const SplatCloud& cloud) {
  const qsplat::QSplatLeaves leaves = qsplat::make_qsplat_leaves(cloud, "test");
  qsplat::QSplatTree tree = qsplat::build_qsplat_tree(leaves);
  const qsplat::EncodedQSplat e = qsplat::encode_qsplat(tree, "");
  return make_qsplat_scene(parse_qsplat(e.bytes, "test.qs"), "test.qs");
}

struct Case {
  const char* name;
  Shape shape;
  int splats;
  float distance;
  bool zbuffer = false;  // the .qs render by --blend zbuffer (the reference stays blended)
  // 0: stratified with exact normals; 1: i.i.d. random, 4: scan lines 4x denser along than
  // across; both with estimate-normals' normals and cover radii, as scanners sample.
  double scan_lines = 0;
  bool cad = false;  // the CAD part (creases, faces seen edge-on) instead of `shape`
  double noise = 0;  // Gaussian noise along the normal, a fraction of the bounding box diagonal
  double min_psnr = 30;
};

SplatCloud cloud_of(const Case& k) {
  if (k.scan_lines == 0) return testing::sample_shape(k.shape, k.splats);
  ShapeOptions shape;
  shape.kind = k.cad                       ? ShapeKind::kCadPart
               : k.shape == Shape::kSphere ? ShapeKind::kSphere
                                           : ShapeKind::kTorus;
  shape.points = static_cast<std::size_t>(k.splats);
  shape.noise = k.noise;
  shape.random = true;
  shape.scan_lines = k.scan_lines > 1 ? k.scan_lines : 0;
  SplatCloud cloud = make_shape(shape);
  cloud.colors.clear();
  estimate_normals(cloud, NormalOptions{});
  return cloud;
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class RenderQSplat : public ::testing::TestWithParam<Case> {};

Camera camera_at(float distance) {
  Camera cam;
  cam.width = 200;
  cam.height = 160;
  cam.fov_y_deg = 40;
  cam.up = {0, 0, 1};
  cam.eye = normalized(Vec3f{0.8f, -0.5f, 0.55f}) * distance;
  cam.target = {0, 0, 0};
  return cam;
}

TEST_P(RenderQSplat, MatchesThePlainSplatRenderAtOnePixel) {
  const Case& k = GetParam();
  const SplatCloud cloud = cloud_of(k);
  RenderScene plain = make_render_scene(SplatCloud(cloud), "test");
  const RenderScene qs = qsplat_scene_of(cloud);
  const Camera cam = camera_at(k.distance);
  RenderOptions options;
  options.planes = {true, false, true};
  // The same blending epsilon for both (the default follows the scene's mean radius).
  options.epsilon = 2 * plain.mean_radius;
  options.cull_backfaces = true;  // for the QSplat render: the traversal culls by the cones
  Framebuffer a, b;
  FrameRenderer renderer;
  renderer.render(plain, cam, options, a);
  if (k.zbuffer) options.blend = BlendMode::kZBuffer;
  const FrameStats s = renderer.render(qs, cam, options, b);

  const auto [pixels, holes, psnr] = testing::compare_inside_mask(a, b, cam.width, cam.height);
  std::printf(
      "%s: mask %d px, holes %d, PSNR %.2f dB, visited %llu, frustum %llu, cone %llu, "
      "selected %llu of %zu\n",
      k.name, pixels, holes, psnr, (unsigned long long)s.lod.visited,
      (unsigned long long)s.lod.culled_frustum, (unsigned long long)s.lod.culled_cone,
      (unsigned long long)s.splats_in, qs.size());
  EXPECT_GT(pixels, 2000);
  EXPECT_LE(holes, pixels / 500);  // measured: at most 14 of 17 000 (21 before leaf pairs)
  EXPECT_GE(psnr, k.min_psnr);
  EXPECT_GT(s.lod.culled_cone, 0u);  // the far side of a closed shape
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, RenderQSplat,
    ::testing::Values(
        Case{"sphere_mid", Shape::kSphere, 20000, 3.0f},
        Case{"sphere_near", Shape::kSphere, 5000, 2.6f},
        Case{"torus_mid", Shape::kTorus, 30000, 3.5f},
        Case{"sphere_mid_zbuffer", Shape::kSphere, 20000, 3.0f, true},
        // Splats of 3 to 8 px, beyond what the z-buffer path is for (below): its
        // unblended discs, the leaves' decoded spheres, measure 38.3 dB against
        // the blended reference (36.8 before leaf groups and pairs, 34.5 when
        // leaves contained their splats, 29.6 to 30 when they were drawn facing
        // the screen).
        Case{"sphere_near_zbuffer", Shape::kSphere, 5000, 2.6f, true},
        Case{"torus_mid_zbuffer", Shape::kTorus, 30000, 3.5f, true},
        Case{"torus_random", Shape::kTorus, 30000, 3.5f, false, 1},
        Case{"sphere_scan_lines", Shape::kSphere, 20000, 3.0f, false, 4},
        // The z-buffer path is for splats of a pixel or two: there its
        // unblended normals cost little.
        Case{"torus_random_zbuffer", Shape::kTorus, 120000, 3.5f, true, 1},
        Case{"sphere_scan_lines_zbuffer", Shape::kSphere, 60000, 3.0f, true, 4},
        Case{"torus_scan_lines_zbuffer", Shape::kTorus, 120000, 3.5f, true, 4},
        Case{"cad_random", Shape::kTorus, 60000, 4.5f, false, 1, true},
        Case{"cad_scan_lines", Shape::kTorus, 60000, 4.5f, false, 4, true},
        Case{"cad_noisy_scan_lines", Shape::kTorus, 60000, 4.5f, false, 4, true, 0.001},
        Case{"torus_noisy_random", Shape::kTorus, 60000, 3.5f, false, 1, false, 0.001}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

TEST(RenderQSplat, LargerThresholdsDrawFewerSplatsAndCullOutsideTheFrustum) {
  const RenderScene qs = qsplat_scene_of(testing::sample_shape(Shape::kTorus, 30000));
  const Projection p = make_projection(camera_at(7.0f));
  LodStats s1, s4, s16;
  const DrawList d1 = select_qsplat(*qs.qsplat, p, 1, true, &s1);
  const DrawList d4 = select_qsplat(*qs.qsplat, p, 4, true, &s4);
  const DrawList d16 = select_qsplat(*qs.qsplat, p, 16, true, &s16);
  EXPECT_GT(d1.count, d4.count);
  EXPECT_GT(d4.count, d16.count);
  // Close up, looking at one side: most of the torus is outside the frustum.
  Camera close = camera_at(1.6f);
  close.fov_y_deg = 20;
  LodStats sc;
  select_qsplat(*qs.qsplat, make_projection(close), 1, true, &sc);
  EXPECT_GT(sc.culled_frustum, 0u);
  // Deterministic for any thread count: same order, same values.
  const DrawList again = select_qsplat(*qs.qsplat, p, 4, true, nullptr);
  ASSERT_EQ(again.count, d4.count);
  for (std::size_t i = 0; i < d4.count; ++i) ASSERT_EQ(again.positions[i], d4.positions[i]);
}

// The normal cones cull back faces only when asked (as --cull-backfaces does for plain splats):
// otherwise the far side of the torus is selected too, behind the near one.
TEST(RenderQSplat, NormalConesCullOnlyWithCullBackfaces) {
  const RenderScene qs = qsplat_scene_of(testing::sample_shape(Shape::kTorus, 30000));
  const Projection p = make_projection(camera_at(7.0f));
  LodStats culled, kept;
  const DrawList one_sided = select_qsplat(*qs.qsplat, p, 1, true, &culled);
  const DrawList two_sided = select_qsplat(*qs.qsplat, p, 1, false, &kept);
  EXPECT_GT(culled.culled_cone, 0u);
  EXPECT_EQ(kept.culled_cone, 0u);
  EXPECT_GT(two_sided.count, one_sided.count + one_sided.count / 4);
}

}  // namespace
}  // namespace splatkit::render
