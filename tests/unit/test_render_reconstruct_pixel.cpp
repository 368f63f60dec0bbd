// reconstruct_pixel on hand-made fragment lists with exact answers: Z-threshold chains, Z-range
// overlaps, the adapted method with surface ids ([IvoMSc] §5.5), the depth window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "render/reconstruct_pixel.h"

namespace splatkit::render {
namespace {

// Fragments on one ray; the fixtures' splats all sit at the origin unless a test says otherwise,
// so the normal fit has no slope to find and gives the weighted mean.
const PixelRay kRay{{0, 0, -1}, {0, 0, 1}};

// The ray of pixel p of a tile of `width` pixels at the image's corner.
PixelRay tile_ray(const Projection& pr, int width, int p) {
  return {pr.eye, pr.ray(float(p % width) + 0.5f, float(p / width) + 0.5f)};
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
  PixelSurface s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
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
  PixelSurface s = reconstruct_pixel(depth, weight, splat, 4, fx.draws(), fx.rasters.data(), o, {}, kRay);
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
  PixelSurface s =
      reconstruct_pixel(depth, weight, splat, 2, d, fx.rasters.data(), o, {0.25f, 0.5f, 0.75f}, kRay);
  EXPECT_NEAR(s.albedo.x, 0.25, 1e-6);
  EXPECT_NEAR(s.albedo.z, 0.75, 1e-6);
  o.window = 0.005f;  // the second fragment is beyond the window: ignored
  s = reconstruct_pixel(depth, weight, splat, 2, d, fx.rasters.data(), o, {}, kRay);
  EXPECT_NEAR(s.normal.x, 1.0, 1e-6);
  EXPECT_EQ(reconstruct_pixel(depth, weight, splat, 0, d, fx.rasters.data(), o, {}, kRay).alpha, 0);
  EXPECT_EQ(depth_window(BlendMode::kZThreshold, 0.1f, 1, 8), 0.8f);
  EXPECT_EQ(depth_window(BlendMode::kZRange, 0.1f, 0.5f, 8), 9.0f);
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
      const PixelSurface s = reconstruct_pixel(depth, weight, order, 6, d, rasters.data(), o, {}, kRay);
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
    const PixelSurface want = reconstruct_pixel(store.depths(p), store.weights(p), store.splats(p),
                                                store.count(p), d, fx.rasters.data(), o, {}, tile_ray(pr, 4, p));
    EXPECT_EQ(std::memcmp(&g[p], &want, sizeof want), 0) << "pixel " << p;
  }
}

}  // namespace
}  // namespace splatkit::render
