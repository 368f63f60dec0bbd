// build_chunk_bvh: every splat in exactly one leaf, leaves within the size limit, boxes that
// contain their children and every disc of their splats, for both split rules, on a city and on
// a scan-line sampled part with noise.
#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "render/chunk_bvh.h"
#include "render/render_scene.h"
#include "splatkit/synthetic_city.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::render {
namespace {

bool contains(const Box3& outer, const Box3& inner) {
  return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
         outer.max.x >= inner.max.x && outer.max.y >= inner.max.y && outer.max.z >= inner.max.z;
}

void check(const RenderScene& scene, uint32_t leaf_size, BvhSplit split) {
  const ChunkBvh bvh = build_chunk_bvh(scene, leaf_size, split);
  ASSERT_EQ(bvh.order.size(), scene.size());
  std::vector<uint32_t> seen(scene.size(), 0);
  uint32_t leaves = 0;
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
    const ChunkBvhNode& x = bvh.nodes[n];
    if (n > 0) {
      EXPECT_LT(x.parent, n);
      EXPECT_TRUE(contains(bvh.nodes[x.parent].box, x.box)) << n;
    }
    if (!x.leaf) {
      EXPECT_EQ(bvh.nodes[x.left].parent, n);
      EXPECT_EQ(bvh.nodes[x.right].parent, n);
      continue;
    }
    ++leaves;
    EXPECT_LE(x.size(), leaf_size);
    EXPECT_GT(x.size(), 0u);
    EXPECT_TRUE(std::is_sorted(bvh.order.begin() + x.left, bvh.order.begin() + x.right));
    for (uint32_t k = x.left; k < x.right; ++k) {
      const uint32_t i = bvh.order[k];
      ++seen[i];
      // The disc's extreme points along each axis lie in the box.
      const Vec3f c = scene.positions[i], nn = scene.normals[i];
      const float r = scene.radii[i];
      const Vec3f e{r * std::sqrt(std::max(0.0f, 1 - nn.x * nn.x)),
                    r * std::sqrt(std::max(0.0f, 1 - nn.y * nn.y)),
                    r * std::sqrt(std::max(0.0f, 1 - nn.z * nn.z))};
      EXPECT_TRUE(contains(x.box, Box3{c - e, c + e})) << i;
    }
  }
  EXPECT_EQ(leaves, bvh.leaf_count);
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](uint32_t s) { return s == 1; }));
  EXPECT_GT(bvh.sah_cost(), 0);
}

RenderScene city(std::size_t points) {
  CityOptions o;
  o.points = points;
  o.blocks = 3;
  return make_render_scene(make_city(o), "city");
}

TEST(ChunkBvh, CityMedianAndSah) {
  const RenderScene scene = city(30000);
  check(scene, 256, BvhSplit::kMedian);
  check(scene, 256, BvhSplit::kSah);
}

TEST(ChunkBvh, ScanLinesWithNoise) {
  ShapeOptions o;
  o.kind = ShapeKind::kCadPart;
  o.points = 20000;
  o.scan_lines = 4;
  o.noise = 0.002;
  const RenderScene scene = make_render_scene(make_shape(o), "cad");
  check(scene, 100, BvhSplit::kMedian);
  check(scene, 100, BvhSplit::kSah);
  check(scene, 1, BvhSplit::kMedian);
}

TEST(ChunkBvh, SahIsNoWorseThanMedianOnTheCity) {
  const RenderScene scene = city(30000);
  const double median = build_chunk_bvh(scene, 128, BvhSplit::kMedian).sah_cost();
  const double sah = build_chunk_bvh(scene, 128, BvhSplit::kSah).sah_cost();
  EXPECT_LE(sah, median * 1.05);
}

TEST(ChunkBvh, SameHierarchyForAnyThreadCount) {
  const RenderScene scene = city(300000);
  ChunkBvh one;
  tbb::task_arena(1).execute([&] { one = build_chunk_bvh(scene, 512); });
  const ChunkBvh two = build_chunk_bvh(scene, 512);
  EXPECT_EQ(one.order, two.order);
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  for (std::size_t n = 0; n < one.nodes.size(); ++n) {
    EXPECT_EQ(one.nodes[n].left, two.nodes[n].left);
    EXPECT_EQ(one.nodes[n].right, two.nodes[n].right);
    EXPECT_EQ(one.nodes[n].box.min, two.nodes[n].box.min);
    EXPECT_EQ(one.nodes[n].box.max, two.nodes[n].box.max);
  }
}

}  // namespace
}  // namespace splatkit::render
