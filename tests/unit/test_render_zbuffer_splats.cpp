// The z-buffer fast path (render/zbuffer_splats.h, --blend zbuffer): which pixels a splat covers,
// which splat a pixel keeps, splats that are not drawn, and images byte-identical for any thread
// count on a real render (plain splats and a QSplat hierarchy).
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <iterator>

#include "formats/read_qsplat.h"
#include "qsplat/build_qsplat_tree.h"
#include "qsplat/encode_qsplat.h"
#include "qsplat/make_qsplat_leaves.h"
#include "render/qsplat_scene.h"
#include "render/zbuffer_splats.h"
#include "splatkit/deterministic_rng.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

// A 20 × 10 image, focal 10 px, looking down +z from the origin: camera space = scene space.
Projection small_projection() {
  Projection p;
  p.eye = {0, 0, 0};
  p.right = {1, 0, 0};
  p.down = {0, 1, 0};
  p.forward = {0, 0, 1};
  p.focal_px = 10;
  p.cx = 10;
  p.cy = 5;
  p.width = 20;
  p.height = 10;
  p.near = 0.1f;
  return p;
}

std::vector<int> covered(const DepthKeyBuffer& b, uint32_t index) {
  std::vector<int> px;
  for (int p = 0; p < b.width * b.height; ++p)
    if (b.keys[p] != kNoSplatKey && DepthKeyBuffer::index_of(b.keys[p]) == index) px.push_back(p);
  return px;
}

TEST(ZBufferSplat, CoversThePixelCentresInsideTheProjectedDisc) {
  const Projection p = small_projection();
  DepthKeyBuffer b;
  b.reset(p.width, p.height);
  // Centre at pixel coordinates (10.5, 5.5) (pixel (10, 5)'s centre), radius 1.2 px: the pixel
  // and its four edge neighbours (distance 1), not the diagonals (distance 1.41).
  const float z = 2;
  ASSERT_TRUE(zbuffer_splat(b, p, {0.05f * z, 0.05f * z, z}, 0.12f * z, 7));
  EXPECT_EQ(covered(b, 7),
            (std::vector<int>{4 * 20 + 10, 5 * 20 + 9, 5 * 20 + 10, 5 * 20 + 11, 6 * 20 + 10}));
  EXPECT_FLOAT_EQ(DepthKeyBuffer::depth_of(b.keys[5 * 20 + 10]), z);
}

TEST(ZBufferSplat, ASplatSmallerThanAPixelStillDrawsThePixelUnderItsCentre) {
  const Projection p = small_projection();
  DepthKeyBuffer b;
  b.reset(p.width, p.height);
  // Projected centre (3.9, 2.1), radius 0.05 px: no pixel centre within reach.
  ASSERT_TRUE(zbuffer_splat(b, p, {-0.61f, -0.29f, 1}, 0.005f, 3));
  EXPECT_EQ(covered(b, 3), (std::vector<int>{2 * 20 + 3}));
}

TEST(ZBufferSplat, ThePixelKeepsTheNearestSplatThenTheLowestIndex) {
  const Projection p = small_projection();
  DepthKeyBuffer b;
  b.reset(p.width, p.height);
  const Vec3f at{0.05f, 0.05f, 1};
  ASSERT_TRUE(zbuffer_splat(b, p, at * 2.0f, 0.01f, 5));
  ASSERT_TRUE(zbuffer_splat(b, p, at * 3.0f, 0.01f, 1));  // farther: loses
  EXPECT_EQ(DepthKeyBuffer::index_of(b.keys[5 * 20 + 10]), 5u);
  ASSERT_TRUE(zbuffer_splat(b, p, at * 2.0f, 0.01f, 9));  // same depth, higher index: loses
  EXPECT_EQ(DepthKeyBuffer::index_of(b.keys[5 * 20 + 10]), 5u);
  ASSERT_TRUE(zbuffer_splat(b, p, at * 2.0f, 0.01f, 2));  // same depth, lower index: wins
  EXPECT_EQ(DepthKeyBuffer::index_of(b.keys[5 * 20 + 10]), 2u);
}

TEST(ZBufferSplat, SplatsReachingPastTheNearPlaneOrOffTheImageAreNotDrawn) {
  const Projection p = small_projection();
  DepthKeyBuffer b;
  b.reset(p.width, p.height);
  EXPECT_FALSE(zbuffer_splat(b, p, {0, 0, 0.15f}, 0.1f, 0));    // reaches depth 0.05 < near
  EXPECT_FALSE(zbuffer_splat(b, p, {0, 0, -2}, 0.1f, 0));       // behind the eye
  EXPECT_FALSE(zbuffer_splat(b, p, {5, 0, 1}, 0.1f, 0));        // 40 px right of the image
  EXPECT_FALSE(zbuffer_splat(b, p, {0, -0.62f, 1}, 0.05f, 0));  // centre row -1.2, reach 0.5 px
  for (uint64_t k : b.keys) ASSERT_EQ(k, kNoSplatKey);
  // Partly off the image: the pixels inside are drawn.
  EXPECT_TRUE(zbuffer_splat(b, p, {-1.0f, 0, 1}, 0.1f, 4));
  EXPECT_FALSE(covered(b, 4).empty());
}

// The pixels whose centre rays meet the disc (c, n, r) in front of the eye, in double: the
// reference for zbuffer_disc.
std::vector<int> ray_cast_disc(const Projection& p, const Vec3f& c, const Vec3f& n, float r) {
  std::vector<int> px;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const double d[3] = {(x + 0.5 - p.cx) / p.focal_px, (y + 0.5 - p.cy) / p.focal_px, 1};
      const double l = n.x * d[0] + n.y * d[1] + n.z * d[2];
      const double t = (double{n.x} * c.x + double{n.y} * c.y + double{n.z} * c.z) / l;
      if (!(t > 0)) continue;
      const double e[3] = {t * d[0] - c.x, t * d[1] - c.y, t * d[2] - c.z};
      if (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] <= double{r} * r) px.push_back(y * p.width + x);
    }
  return px;
}

TEST(ZBufferDisc, CoversThePixelsWhoseRaysMeetTheTiltedDisc) {
  const Projection p = small_projection();
  DeterministicRng rng(11);
  int compared = 0, mismatched = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3f c{static_cast<float>(rng.uniform(-0.8, 0.8)),
                  static_cast<float>(rng.uniform(-0.4, 0.4)),
                  static_cast<float>(rng.uniform(1.0, 3.0))};
    const Vec3f n = normalized(Vec3f{static_cast<float>(rng.uniform(-1, 1)),
                                     static_cast<float>(rng.uniform(-1, 1)),
                                     static_cast<float>(rng.uniform(-1, 1))});
    const float r = static_cast<float>(rng.uniform(0.06, 0.4)) * c.z;  // 0.6 to 4 px
    DepthKeyBuffer b;
    b.reset(p.width, p.height);
    const std::vector<int> want = ray_cast_disc(p, c, n, r);
    const bool drawn = zbuffer_disc(b, p, c, [&] { return n; }, r, 1);
    const std::vector<int> got = covered(b, 1);
    if (want.empty()) {  // edge-on or between pixel centres: the pixel under the centre, if any
      EXPECT_LE(got.size(), 1u);
      continue;
    }
    EXPECT_TRUE(drawn);
    ++compared;
    // Float against double: a pixel centre on the ellipse's edge may go either way.
    std::vector<int> diff;
    std::set_symmetric_difference(want.begin(), want.end(), got.begin(), got.end(),
                                  std::back_inserter(diff));
    mismatched += diff.size() > 0;
    EXPECT_LE(diff.size(), 1u) << "disc " << k;
  }
  EXPECT_GT(compared, 300);
  EXPECT_LE(mismatched, 4);
}

TEST(ZBufferDisc, AnEdgeOnDiscDrawsOnlyThePixelUnderItsCentre) {
  const Projection p = small_projection();
  DepthKeyBuffer b;
  b.reset(p.width, p.height);
  // Centre on pixel (10, 5)'s centre ray, 3 px across, its plane through the eye: as a
  // screen-aligned disc it would cover 29 pixels.
  const float z = 2;
  ASSERT_TRUE(zbuffer_disc(
      b, p, {0.05f * z, 0.05f * z, z}, [] { return normalized(Vec3f{1, 0, -0.05f}); }, 0.3f * z, 7));
  EXPECT_EQ(covered(b, 7), (std::vector<int>{5 * 20 + 10}));
  // Facing the eye it covers about the screen-aligned disc's pixels (the exact projection of a
  // disc facing the eye off the axis is a little smaller than r·focal/z).
  DepthKeyBuffer round, facing;
  round.reset(p.width, p.height);
  facing.reset(p.width, p.height);
  const Vec3f c{0.05f * z, 0.05f * z, z};
  ASSERT_TRUE(zbuffer_splat(round, p, c, 0.3f * z, 2));
  ASSERT_TRUE(zbuffer_disc(facing, p, c, [&] { return normalized(c) * -1.0f; }, 0.3f * z, 2));
  EXPECT_NEAR(static_cast<double>(covered(facing, 2).size()),
              static_cast<double>(covered(round, 2).size()), 4.0);
}

Camera render_camera() {
  Camera cam;
  cam.width = 240;
  cam.height = 180;
  cam.eye = {2.2f, -1.6f, 1.4f};
  return cam;
}

// Renders `scene` with --blend zbuffer on `threads` threads.
Framebuffer render_on(const RenderScene& scene, int threads, FrameStats* stats = nullptr) {
  const Camera cam = render_camera();
  RenderOptions o;
  o.blend = BlendMode::kZBuffer;
  o.planes = {true, true, true};
  Framebuffer out;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    FrameRenderer r;
    const FrameStats s = r.render(scene, cam, o, out);
    if (stats) *stats = s;
  });
  return out;
}

void expect_identical(const Framebuffer& a, const Framebuffer& b) {
  EXPECT_EQ(a.rgb8, b.rgb8);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.normal, b.normal);
}

TEST(ZBufferFrame, ByteIdenticalForAnyThreadCountAndHoleFree) {
  using testing::Shape;
  const SplatCloud cloud = testing::sample_shape(Shape::kTorus, 40000);
  const RenderScene plain = make_render_scene(SplatCloud(cloud), "test");
  FrameStats s;
  const Framebuffer one = render_on(plain, 1, &s);
  expect_identical(one, render_on(plain, 2));
  EXPECT_EQ(s.splats_in, cloud.size());
  EXPECT_GT(s.splats_drawn, cloud.size() / 2);
  // Inside the silhouette of the blended render (its mask eroded by a pixel) nothing is open.
  Framebuffer blended;
  RenderOptions o;
  o.planes = {true, false, true};
  FrameRenderer().render(plain, render_camera(), o, blended);
  const auto inside = testing::morph(
      [&] {
        std::vector<uint8_t> m(blended.alpha.size());
        for (std::size_t p = 0; p < m.size(); ++p) m[p] = blended.alpha[p] > 0;
        return m;
      }(),
      240, 180, false);
  int holes = 0, pixels = 0;
  for (std::size_t p = 0; p < inside.size(); ++p) {
    holes += inside[p] && !(one.alpha[p] > 0);
    pixels += inside[p];
  }
  EXPECT_GT(pixels, 5000);
  EXPECT_EQ(holes, 0);

  const qsplat::QSplatLeaves leaves = qsplat::make_qsplat_leaves(cloud, "test");
  qsplat::QSplatTree tree = qsplat::build_qsplat_tree(leaves);
  const qsplat::EncodedQSplat e = qsplat::encode_qsplat(tree, "");
  const RenderScene qs = make_qsplat_scene(parse_qsplat(e.bytes, "test.qs"), "test.qs");
  const Framebuffer q1 = render_on(qs, 1, &s);
  expect_identical(q1, render_on(qs, 2));
  EXPECT_GT(s.lod.visited, s.splats_in);
  EXPECT_GT(s.splats_drawn, 1000u);
}

}  // namespace
}  // namespace splatkit::render
