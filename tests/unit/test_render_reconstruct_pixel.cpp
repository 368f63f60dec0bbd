// reconstruct_pixel on hand-made fragment lists with exact answers: Z-threshold chains, Z-range
// overlaps, the adapted method with surface ids ([IvoMSc] §5.5), the depth window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "render/reconstruct_pixel.h"

namespace splatkit::render {
namespace {

// The ray along the camera's forward axis. The fixtures' splats are small on screen (ring2 = 0:
// no ring, SplatRaster's value-initialised fields) unless a test says otherwise, so the normal
// is the weighted mean.
const PixelRay kRay{0, 0};

// The ray of pixel p of a tile of `width` pixels at the image's corner.
PixelRay tile_ray(const Projection& pr, int width, int p) {
  return pixel_ray(pr, p % width, p / width);
}

Projection test_projection() {
  Camera cam;
  cam.width = 4;
  cam.height = 1;
  cam.eye = {0, 0, -3};
  cam.target = {0, 0, 0};
  cam.up = {0, 1, 0};
  return make_projection(cam);
}

// Four splats: normals along x, y, z, -x; colours red, green, blue, white; depth ranges given.
struct Fixture {
  std::vector<Vec3f> pos{4}, normals{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}};
  std::vector<float> radii{1, 1, 1, 1};
  std::vector<Vec3f> colors{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  std::vector<uint32_t> ids{0, 0, 0, 0};
  std::vector<SplatRaster> rasters{4};
  DrawList draws() {
    for (int i = 0; i < 4; ++i) rasters[i].normal = normals[i];
    return {4, pos.data(), normals.data(), radii.data(), colors.data(), ids.data()};
  }
  void range(int i, float lo, float hi) {
    rasters[i].zmin = lo;
    rasters[i].zmax = hi;
  }
};

TEST(RenderReconstructPixel, ZThresholdChainsConsecutiveFragments) {
  Fixture fx;
  // Given out of order: depths 1.0 (splat 1), 1.08 (splat 0), 1.15 (splat 2), 3.0 (splat 3).
  const float depth[] = {1.08f, 3.0f, 1.0f, 1.15f};
  const float weight[] = {1, 1, 3, 1};
  const uint32_t splat[] = {0, 3, 1, 2};
  BlendOptions o{BlendMode::kZThreshold, 0.1f};
  PixelSurface s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o,
                                     {0.5f, 0.5f, 0.5f}, kRay);
  // 1.0 -> 1.08 -> 1.15 chain (steps < 0.1); 3.0 is another surface.
  EXPECT_FLOAT_EQ(s.alpha, 1);
  EXPECT_NEAR(s.normal.x, 1.0 / 5, 1e-6);
  EXPECT_NEAR(s.normal.y, 3.0 / 5, 1e-6);
  EXPECT_NEAR(s.normal.z, 1.0 / 5, 1e-6);
  EXPECT_NEAR(s.albedo.y, 3.0 / 5, 1e-6);
  EXPECT_NEAR(s.depth, (1.08 + 3 * 1.0 + 1.15) / 5, 1e-6);
  // A smaller threshold stops the chain after the first fragment.
  o.epsilon = 0.05f;
  s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.y, 1.0, 1e-6);
  EXPECT_NEAR(s.depth, 1.0, 1e-6);
}

TEST(RenderReconstructPixel, ZRangeJoinsOverlappingDepthRanges) {
  Fixture fx;
  fx.range(0, 0.9f, 1.1f);
  fx.range(1, 1.05f, 1.3f);  // overlaps splat 0
  fx.range(2, 1.25f, 1.5f);  // overlaps the union [0.9, 1.3]
  fx.range(3, 1.6f, 2.0f);   // gap
  const float depth[] = {1.0f, 1.2f, 1.3f, 1.7f};
  const float weight[] = {1, 1, 1, 1};
  const uint32_t splat[] = {0, 1, 2, 3};
  BlendOptions o{BlendMode::kZRange, 0};
  PixelSurface s =
      reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.x, 1.0 / 3, 1e-6);
  EXPECT_NEAR(s.normal.y, 1.0 / 3, 1e-6);
  EXPECT_NEAR(s.normal.z, 1.0 / 3, 1e-6);
  fx.range(1, 1.15f, 1.3f);  // now a gap after splat 0
  s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.x, 1.0, 1e-6);
}

TEST(RenderReconstructPixel, OtherSurfaceIdsAreSetAsideNotBlended) {
  Fixture fx;
  fx.ids = {7, 9, 7, 7};  // splat 1 lies between splats 0 and 2 in depth but is another surface
  const float depth[] = {1.0f, 1.05f, 1.1f, 5.0f};
  const float weight[] = {1, 1, 1, 1};
  const uint32_t splat[] = {0, 1, 2, 3};
  BlendOptions o{BlendMode::kZThreshold, 0.12f};
  PixelSurface s =
      reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
  EXPECT_EQ(s.surface_id, 7u);
  EXPECT_NEAR(s.normal.x, 0.5, 1e-6);  // splats 0 and 2 only
  EXPECT_NEAR(s.normal.y, 0.0, 1e-6);
  EXPECT_NEAR(s.normal.z, 0.5, 1e-6);
  // Classic Z-threshold (one surface id) would blend all three.
  fx.ids = {0, 0, 0, 0};
  s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.y, 1.0 / 3, 1e-6);
}

TEST(RenderReconstructPixel, DefaultAlbedoWithoutColoursAndDepthWindow) {
  Fixture fx;
  DrawList d = fx.draws();
  d.colors = nullptr;
  const float depth[] = {1.0f, 1.01f};
  const float weight[] = {1, 1};
  const uint32_t splat[] = {0, 1};
  BlendOptions o{BlendMode::kZThreshold, 0.1f};
  PixelSurface s = reconstruct_pixel(depth, weight, splat, 2, d, fx.rasters.data(), o,
                                     {0.25f, 0.5f, 0.75f}, kRay);
  EXPECT_NEAR(s.albedo.x, 0.25, 1e-6);
  EXPECT_NEAR(s.albedo.z, 0.75, 1e-6);
  o.window = 0.005f;  // the second fragment is beyond the window: ignored
  s = reconstruct_pixel(depth, weight, splat, 2, d, fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.x, 1.0, 1e-6);
  EXPECT_EQ(reconstruct_pixel(depth, weight, splat, 0, d, fx.rasters.data(), o, {}, kRay).alpha, 0);
  EXPECT_EQ(depth_window(BlendMode::kZThreshold, 0.1f, 1, 8), 0.8f);
  // Z-range: ranges of discs with their rings (setup_splats.h).
  EXPECT_EQ(depth_window(BlendMode::kZRange, 0.1f, 0.5f, 8), 9.0f * kRingScale);
}

// The fragments' order in the A-buffer changes nothing, not even the last bit: they are sorted by
// depth, ties by splat index, before anything is summed. Splats 4 and 2 tie at the nearest depth
// and belong to different surfaces: the lower index, 2, comes first and names the surface.
TEST(RenderReconstructPixel, AnyArrivalOrderGivesTheSameBits) {
  std::vector<Vec3f> pos(6),
      normals{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.6f, 0.8f, 0}, {0, 0.6f, 0.8f}, {0.8f, 0, 0.6f}};
  std::vector<float> radii(6, 1.0f);
  std::vector<Vec3f> colors{{0.1f, 0.2f, 0.3f}, {0.7f, 0.1f, 0.9f}, {0.3f, 0.3f, 0.1f},
                            {0.5f, 0.9f, 0.2f}, {0.9f, 0.4f, 0.6f}, {0.2f, 0.8f, 0.7f}};
  std::vector<uint32_t> ids{7, 7, 7, 7, 9, 7};
  std::vector<SplatRaster> rasters(6);
  for (int i = 0; i < 6; ++i) rasters[i].normal = normals[i];
  const float depth_of[] = {1.07f, 1.05f, 1.0f, 1.13f, 1.0f, 1.0333f};
  const float weight_of[] = {0.3f, 0.71f, 0.13f, 0.9f, 0.55f, 0.37f};
  for (bool with_ids : {false, true}) {
    const DrawList d{6,
                     pos.data(),
                     normals.data(),
                     radii.data(),
                     colors.data(),
                     with_ids ? ids.data() : nullptr};
    const BlendOptions o{BlendMode::kZThreshold, 0.05f};
    uint32_t order[] = {0, 1, 2, 3, 4, 5};
    PixelSurface first;
    int permutations = 0;
    do {
      float depth[6], weight[6];
      for (int k = 0; k < 6; ++k) {
        depth[k] = depth_of[order[k]];
        weight[k] = weight_of[order[k]];
      }
      const PixelSurface s =
          reconstruct_pixel(depth, weight, order, 6, d, rasters.data(), o, {}, kRay);
      if (permutations++ == 0) first = s;
      ASSERT_EQ(std::memcmp(&s, &first, sizeof s), 0) << "permutation " << permutations;
    } while (std::next_permutation(order, order + 6));
    EXPECT_EQ(first.surface_id, with_ids ? 7u : 0u);
    EXPECT_EQ(first.alpha, 1);
  }
}

// reconstruct_pixels over a FragmentStore gives reconstruct_pixel's bits for every covered pixel,
// alpha 0 for the empty ones, and counts covered and overflowed pixels.
TEST(RenderReconstructPixel, TileFormIsThePixelFormPerPixel) {
  Fixture fx;
  const DrawList d = fx.draws();
  const BlendOptions o{BlendMode::kZThreshold, 0.1f};
  FragmentStore store;
  store.reset(4, 3, o.window);
  store.add(0, 1.0f, 0.5f, 2);
  store.add(0, 1.05f, 0.25f, 0);
  store.add(2, 2.0f, 1.0f, 1);
  for (int k = 0; k < 4; ++k) store.add(3, 1.0f + 0.01f * k, 0.1f * (k + 1), k);  // overflows
  std::vector<PixelSurface> g(4);
  uint64_t overflowed = 0;
  const Projection pr = test_projection();
  EXPECT_EQ(reconstruct_pixels(store, 4, d, fx.rasters.data(), o, {}, {&pr, 0, 0, 4}, g.data(),
                               overflowed),
            3);
  EXPECT_EQ(overflowed, 1u);
  EXPECT_EQ(g[1].alpha, 0);
  for (int p : {0, 2, 3}) {
    const PixelSurface want =
        reconstruct_pixel(store.depths(p), store.weights(p), store.splats(p), store.count(p), d,
                          fx.rasters.data(), o, {}, tile_ray(pr, 4, p));
    EXPECT_EQ(std::memcmp(&g[p], &want, sizeof want), 0) << "pixel " << p;
  }
}

// Splats large on screen (ring2 > 1) for the fit tests: centres at camera-space (cx, cy), facing
// the eye (nc < 0), normal `n`.
SplatRaster big_splat(float cx, float cy, const Vec3f& n) {
  SplatRaster r{};
  r.nc = -1;
  r.normal = n;
  r.cx = cx;
  r.cy = cy;
  r.ring2 = 1.5625f;
  return r;
}

// A normal field linear over the centres, n(c) = n0 + G c, is reproduced exactly at the pixel's
// surface point (here the ray's point at the blended depth 2: camera-space (0.02, −0.01)), where
// the weighted mean is pulled towards the heavier splats. Ring fragments count for the normal
// only.
TEST(RenderReconstructPixel, FitReproducesALinearNormalField) {
  const Vec3f n0{0.1f, -0.2f, -1.0f}, ga{0.8f, 0.1f, 0.05f}, gb{-0.2f, 0.6f, 0.1f};
  const float cx[] = {0.05f, -0.03f, 0.02f, 0.07f, -0.04f};
  const float cy[] = {0.01f, 0.04f, -0.05f, -0.02f, 0.0f};
  std::vector<SplatRaster> rasters;
  std::vector<Vec3f> pos(5), normals, colors;
  for (int k = 0; k < 5; ++k) {
    normals.push_back(n0 + ga * cx[k] + gb * cy[k]);
    rasters.push_back(big_splat(cx[k], cy[k], normals.back()));
    colors.push_back({0.1f * k, 0.5f, 0.5f});
  }
  std::vector<float> radii(5, 0.1f);
  const DrawList d{5, pos.data(), normals.data(), radii.data(), colors.data()};
  const float depth[] = {2.0f, 2.0f, 2.0f, 2.0f, 2.0f};
  const float weight[] = {0.9f, 0.2f, 0.5f, -0.1f, -0.05f};  // two ring fragments
  const uint32_t splat[] = {0, 1, 2, 3, 4};
  const BlendOptions o{BlendMode::kZThreshold, 0.1f};
  const PixelRay ray{0.01f, -0.005f};
  const PixelSurface s = reconstruct_pixel(depth, weight, splat, 5, d, rasters.data(), o, {}, ray);
  const Vec3f want = n0 + ga * 0.02f + gb * -0.01f;
  // Exact but for the ridge term, which shortens the slopes by a few per cent.
  EXPECT_NEAR(s.normal.x, want.x, 1e-3);
  EXPECT_NEAR(s.normal.y, want.y, 1e-3);
  EXPECT_NEAR(s.normal.z, want.z, 1e-3);
  EXPECT_EQ(s.alpha, 1);
  EXPECT_NEAR(s.depth, 2.0, 1e-6);
  EXPECT_NEAR(s.albedo.x, (0.9 * 0 + 0.2 * 0.1 + 0.5 * 0.2) / 1.6, 1e-6);  // discs only
}

// A fragment facing away within the threshold of one facing the eye (the far side of a thin
// part) is set aside: the normal is the front one's. Alone, it stays (a surface seen from
// behind).
TEST(RenderReconstructPixel, BackFacesBehindAFrontFaceAreSetAside) {
  std::vector<SplatRaster> rasters{big_splat(0, 0, {0, 0, -1}), big_splat(0, 0, {0, 0.6f, 0.8f})};
  rasters[1].nc = 0.5f;  // faces away
  std::vector<Vec3f> pos(2), normals{{0, 0, -1}, {0, 0.6f, 0.8f}};
  std::vector<float> radii(2, 0.1f);
  const DrawList d{2, pos.data(), normals.data(), radii.data()};
  const float depth[] = {1.0f, 1.02f};
  const float weight[] = {0.3f, 1.0f};
  const uint32_t splat[] = {0, 1};
  const BlendOptions o{BlendMode::kZThreshold, 0.1f};
  PixelSurface s = reconstruct_pixel(depth, weight, splat, 2, d, rasters.data(), o, {}, kRay);
  EXPECT_EQ(s.normal.x, 0);
  EXPECT_EQ(s.normal.y, 0);
  EXPECT_EQ(s.normal.z, -1);
  EXPECT_NEAR(s.depth, 1.0, 1e-6);
  s = reconstruct_pixel(depth + 1, weight + 1, splat + 1, 1, d, rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.y, 0.6, 1e-6);
}

// Ring fragments cover nothing unless their splats' centres surround the pixel, or they face the
// eye in front of a surface that faces away: then the pixel is a pinhole among them, and they
// cover it, even in front of a deeper surface.
TEST(RenderReconstructPixel, RingFragmentsCoverOnlyPinholes) {
  std::vector<SplatRaster> rasters{
      big_splat(0.1f, 0, {0, 0, -1}), big_splat(-0.05f, 0.09f, {0, 0, -1}),
      big_splat(-0.05f, -0.09f, {0, 0, -1}), big_splat(0, 0, {0, 1, 0})};
  std::vector<Vec3f> pos(4), normals(4, Vec3f{0, 0, -1}),
      colors{{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  std::vector<float> radii(4, 0.1f);
  const DrawList d{4, pos.data(), normals.data(), radii.data(), colors.data()};
  const float depth[] = {1.0f, 1.01f, 1.02f, 5.0f};
  const float weight[] = {-0.1f, -0.1f, -0.1f, 1.0f};
  const uint32_t splat[] = {0, 1, 2, 3};
  const BlendOptions o{BlendMode::kZThreshold, 0.1f};
  // Two ring fragments: an edge, not a hole; the surface behind shows.
  PixelSurface s =
      reconstruct_pixel(depth + 1, weight + 1, splat + 1, 3, d, rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.depth, 5.0, 1e-6);
  EXPECT_EQ(s.albedo.z, 1);
  EXPECT_EQ(
      reconstruct_pixel(depth + 1, weight + 1, splat + 1, 2, d, rasters.data(), o, {}, kRay).alpha,
      0);
  // The same two in front of a surface facing away: a back face seen through a gap, covered.
  rasters[3].nc = 0.5f;
  s = reconstruct_pixel(depth + 1, weight + 1, splat + 1, 3, d, rasters.data(), o, {}, kRay);
  EXPECT_EQ(s.alpha, 1);
  EXPECT_NEAR(s.depth, 1.015, 1e-6);
  EXPECT_EQ(s.albedo.x, 1);
  rasters[3].nc = -1;
  // Three around the pixel: a hole, covered by them, alone or in front of another surface.
  EXPECT_EQ(reconstruct_pixel(depth, weight, splat, 3, d, rasters.data(), o, {}, kRay).alpha, 1);
  s = reconstruct_pixel(depth, weight, splat, 4, d, rasters.data(), o, {}, kRay);
  EXPECT_EQ(s.alpha, 1);
  EXPECT_NEAR(s.depth, 1.01, 1e-6);
  EXPECT_EQ(s.albedo.x, 1);
  EXPECT_EQ(s.normal.z, -1);
}

}  // namespace
}  // namespace splatkit::render
