// OcclusionCuller: (1) images byte-identical to rendering every splat, for every mode, both
// A-buffer blends, over a city walkthrough and orbit views of a scan-line sampled part with
// noise, while culling really happens; (2) a scene with a known visible set (a wall with boxes
// behind it, boxes in front and beside it): from several cameras the hidden boxes are culled
// (no leaf of their own, and with the per-splat test no splat of theirs, is drawn), the splats
// the frame truly shows (count_visible_splats.h; those the renderer draws) never are; (3) the
// splats chc++ draws do not depend on the number of threads or their timing.
#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <set>

#include "render/chunk_bvh.h"
#include "render/count_visible_splats.h"
#include "render/frame_renderer.h"
#include "render/occlusion_culler.h"
#include "render/reconstruct_pixel.h"
#include "render/subset_scene.h"
#include "splatkit/synthetic_city.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::render {
namespace {

const OcclusionMode kModes[] = {OcclusionMode::kFrustum, OcclusionMode::kHierarchical,
                                OcclusionMode::kChc, OcclusionMode::kChcPlusPlus};

float margin_of(const RenderScene& s, const RenderOptions& o) {
  const float eps = o.epsilon > 0 ? o.epsilon : 2.0f * s.mean_radius;
  return depth_window(o.blend, eps, s.max_radius, o.max_fragments);
}

Camera camera_at(Vec3f eye, Vec3f target, int w, int h) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.width = w;
  c.height = h;
  c.fov_y_deg = 60;
  return c;
}

// Renders every camera with every mode and compares with the full render; returns the splats
// culled by occlusion queries over all modes and frames.
uint64_t expect_identical(const RenderScene& scene, const std::vector<Camera>& cameras,
                          const RenderOptions& options, uint32_t leaf) {
  const ChunkBvh bvh = build_chunk_bvh(scene, leaf);
  FrameRenderer renderer;
  std::vector<Framebuffer> full(cameras.size());
  for (std::size_t f = 0; f < cameras.size(); ++f)
    renderer.render(scene, cameras[f], options, full[f]);
  uint64_t culled = 0;
  for (OcclusionMode mode : kModes) {
    OcclusionCuller culler(scene, bvh);
    RenderScene subset;
    for (std::size_t f = 0; f < cameras.size(); ++f) {
      OcclusionStats stats;
      const auto& draw = culler.cull(make_projection(cameras[f]), mode, margin_of(scene, options),
                                     options.cull_backfaces, stats);
      EXPECT_TRUE(std::is_sorted(draw.begin(), draw.end()));
      EXPECT_EQ(stats.splats_drawn, draw.size());
      if (mode != OcclusionMode::kFrustum) culled += stats.culled_occlusion;
      subset_scene(scene, draw, subset);
      Framebuffer img;
      renderer.render(subset, cameras[f], options, img);
      EXPECT_EQ(img.rgb8.size(), full[f].rgb8.size());
      if (img.rgb8.size() != full[f].rgb8.size() || img.depth.size() != full[f].depth.size())
        return culled;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < img.rgb8.size(); ++i) differ += img.rgb8[i] != full[f].rgb8[i];
      EXPECT_EQ(differ, 0u) << occlusion_mode_name(mode) << " frame " << f;
      EXPECT_EQ(img.depth.size(), full[f].depth.size());
      EXPECT_EQ(
          0, std::memcmp(img.depth.data(), full[f].depth.data(), img.depth.size() * sizeof(float)))
          << occlusion_mode_name(mode) << " frame " << f;
    }
  }
  return culled;
}

TEST(OcclusionCuller, CityWalkthroughIsByteIdentical) {
  CityOptions o;
  o.points = 120000;
  o.blocks = 4;
  o.walk_frames = 6;
  const RenderScene scene = make_render_scene(make_city(o), "city");
  std::vector<Camera> cameras;
  for (const CityCamera& c : city_walkthrough(o))
    cameras.push_back(camera_at(c.eye, c.target, 240, 135));
  RenderOptions options;
  options.planes.aovs = true;
  EXPECT_GT(expect_identical(scene, cameras, options, 256), 0u);
  options.blend = BlendMode::kZRange;
  EXPECT_GT(expect_identical(scene, cameras, options, 256), 0u);
}

TEST(OcclusionCuller, ScanLinesWithNoiseIsByteIdentical) {
  ShapeOptions o;
  o.kind = ShapeKind::kCadPart;
  o.points = 40000;
  o.scan_lines = 4;
  o.noise = 0.001;
  const RenderScene scene = make_render_scene(make_shape(o), "cad");
  std::vector<Camera> cameras;
  for (int k = 0; k < 4; ++k) {
    Camera c =
        orbit_camera(scene.bounds, 30.0f + 40 * k, 20, std::nullopt, {0, 0, 1}, 40, 200, 150);
    cameras.push_back(c);
  }
  RenderOptions options;
  options.planes.aovs = true;
  EXPECT_GT(expect_identical(scene, cameras, options, 64), 0u);
  options.cull_backfaces = true;
  expect_identical(scene, cameras, options, 64);
  // Few A-buffer slots: most covered pixels overflow, with equal depths among the fragments of
  // coplanar splats; the splats culled one by one must still change no slot's outcome.
  options.cull_backfaces = false;
  options.max_fragments = 2;
  EXPECT_GT(expect_identical(scene, cameras, options, 64), 0u);
}

// A grid of splats on an axis-aligned rectangle from `origin` along `a` and `b`.
void add_rect(SplatCloud& c, Vec3f origin, Vec3f a, Vec3f b, Vec3f normal, float step) {
  const int na = int(std::lround(norm(a) / step)), nb = int(std::lround(norm(b) / step));
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < na; ++i) {
      c.positions.push_back(origin + a * ((i + 0.5f) / na) + b * ((j + 0.5f) / nb));
      c.normals.push_back(normal);
      c.radii.push_back(step * 0.75f);
    }
}

// A unit cube's six faces from corner `lo`.
void add_cube(SplatCloud& c, Vec3f lo, float step) {
  const Vec3f x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  add_rect(c, lo, y, z, x * -1.0f, step);
  add_rect(c, lo + x, y, z, x, step);
  add_rect(c, lo, x, z, y * -1.0f, step);
  add_rect(c, lo + y, x, z, y, step);
  add_rect(c, lo, x, y, z * -1.0f, step);
  add_rect(c, lo + z, x, y, z, step);
}

TEST(OcclusionCuller, WallHidesTheBoxesBehindIt) {
  SplatCloud cloud;
  const float step = 0.1f;
  add_rect(cloud, {0, -4, 0}, {0, 8, 0}, {0, 0, 4}, {-1, 0, 0}, step);  // the wall, facing -x
  struct Range {
    std::size_t begin, end;
    bool visible;
  };
  std::vector<Range> boxes;
  auto box = [&](Vec3f lo, bool visible) {
    const std::size_t b = cloud.positions.size();
    add_cube(cloud, lo, step);
    boxes.push_back({b, cloud.positions.size(), visible});
  };
  for (float y : {-3.0f, -0.5f, 2.0f}) box({2, y, 0.5f}, false);  // behind the wall
  box({-3, -2.5f, 0.5f}, true);                                   // in front of it
  box({-3, 1.5f, 0.5f}, true);
  box({2, 8.0f, 0.5f}, true);  // beside it, behind its plane
  const RenderScene scene = make_render_scene(std::move(cloud), "wall");
  const ChunkBvh bvh = build_chunk_bvh(scene, 32);
  // A leaf is drawn or culled whole: a hidden box's splats that share a leaf with anything else
  // may be drawn. Every box must have leaves of its own for the test to say something.
  std::vector<int> owner(scene.size(), -1);  // box of each splat, -1 for the wall
  for (std::size_t b = 0; b < boxes.size(); ++b)
    for (std::size_t i = boxes[b].begin; i < boxes[b].end; ++i) owner[i] = int(b);
  std::vector<int> leaf_owner(bvh.nodes.size(), -2);  // a box, or -1: shared or wall
  std::vector<int> own_leaves(boxes.size(), 0);
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
    const ChunkBvhNode& x = bvh.nodes[n];
    if (!x.leaf) continue;
    int o = owner[bvh.order[x.left]];
    for (uint32_t k = x.left; k < x.right; ++k)
      if (owner[bvh.order[k]] != o) o = -1;
    leaf_owner[n] = o;
    if (o >= 0) ++own_leaves[o];
  }
  for (int c : own_leaves) ASSERT_GT(c, 10);
  RenderOptions options;
  for (OcclusionMode mode :
       {OcclusionMode::kHierarchical, OcclusionMode::kChc, OcclusionMode::kChcPlusPlus}) {
    OcclusionCuller culler(scene, bvh);
    for (float y : {-1.0f, 0.0f, 1.0f, 0.5f, -0.5f, 0.0f, 0.0f, 1.0f}) {
      const Camera cam = camera_at({-12, y, 2}, {0, y, 2}, 320, 180);
      OcclusionStats stats;
      const auto& draw =
          culler.cull(make_projection(cam), mode, margin_of(scene, options), false, stats);
      const std::set<uint32_t> drawn(draw.begin(), draw.end());
      // The splats some pixel shows, less those the renderer's setup does not draw at all (seen
      // edge on, between pixel centres: the z-buffer pass draws them as screen-aligned discs).
      std::vector<uint32_t> shown = visible_splats(scene, make_projection(cam), false);
      {
        std::vector<SplatBounds> bounds(shown.size());
        DepthPassScratch scratch;
        draw_depth(scene, shown.data(), shown.size(), make_projection(cam), false, nullptr, scratch,
                   bounds.data());
        std::size_t kept = 0;
        for (std::size_t k = 0; k < shown.size(); ++k)
          if (bounds[k].drawn()) shown[kept++] = shown[k];
        shown.resize(kept);
      }
      ASSERT_GT(shown.size(), 100u);
      std::size_t shown_drawn = 0;
      for (uint32_t i : shown) shown_drawn += drawn.count(i);
      EXPECT_EQ(shown_drawn, shown.size()) << occlusion_mode_name(mode) << " y " << y;
      EXPECT_GT(stats.splats_culled, 0u) << occlusion_mode_name(mode) << " y " << y;
      for (std::size_t b = 0; b < boxes.size(); ++b) {
        const Range& r = boxes[b];
        std::size_t count = 0, count_shown = 0;
        for (std::size_t i = r.begin; i < r.end; ++i) count += drawn.count(uint32_t(i));
        for (uint32_t i : shown) count_shown += i >= r.begin && i < r.end;
        if (r.visible) {
          // Its faces towards the camera show; those behind them may be culled splat by splat.
          EXPECT_GT(count_shown, 50u) << " box " << b;
          EXPECT_GE(count, count_shown) << occlusion_mode_name(mode) << " y " << y;
          continue;
        }
        EXPECT_EQ(count_shown, 0u) << " box " << b;
        EXPECT_EQ(count, 0u) << occlusion_mode_name(mode) << " y " << y << " box " << b;
        int leaves_drawn = 0;
        for (uint32_t n = 0; n < bvh.nodes.size(); ++n)
          if (leaf_owner[n] == int(b))
            leaves_drawn += drawn.count(bvh.order[bvh.nodes[n].left]) != 0;
        EXPECT_EQ(leaves_drawn, 0) << occlusion_mode_name(mode) << " y " << y << " box " << b;
      }
    }
  }
}

// The depth pass runs on several threads; the splats drawn must not depend on how many, nor on
// their timing: one thread and two (twice) give the same lists.
TEST(OcclusionCuller, DrawnSplatsDoNotDependOnThreads) {
  CityOptions o;
  o.points = 120000;
  o.blocks = 4;
  o.walk_frames = 6;
  const RenderScene scene = make_render_scene(make_city(o), "city");
  const ChunkBvh bvh = build_chunk_bvh(scene, 256);
  RenderOptions options;
  auto lists = [&](int threads) {
    std::vector<std::vector<uint32_t>> out;
    tbb::task_arena arena(threads);
    arena.execute([&] {
      OcclusionCuller culler(scene, bvh);
      for (const CityCamera& c : city_walkthrough(o)) {
        OcclusionStats stats;
        out.push_back(culler.cull(make_projection(camera_at(c.eye, c.target, 480, 270)),
                                  OcclusionMode::kChcPlusPlus, margin_of(scene, options), false,
                                  stats));
      }
    });
    return out;
  };
  const auto one = lists(1), two = lists(2), again = lists(2);
  ASSERT_EQ(one.size(), 6u);
  for (std::size_t f = 0; f < one.size(); ++f) {
    EXPECT_EQ(one[f], two[f]) << "frame " << f;
    EXPECT_EQ(two[f], again[f]) << "frame " << f;
  }
}

}  // namespace
}  // namespace splatkit::render
