// A bounding-volume hierarchy of splat chunks for occlusion culling (occlusion_culler.h): binary
// nodes with axis-aligned boxes, leaves of at most `leaf_size` splats. Built once per scene at
// load; the scene's arrays are not reordered (leaves hold index lists), so a frame drawn from any
// subset of leaves keeps the scene's splat order and with it the renderer's tie-breaks.
//
// A splat's box is its disc's exact axis-aligned box: centre ± r·√(1 − n_i²) per axis (ellipses:
// ± the larger semi-axis). A node's box is the union of its splats' boxes, so every fragment of
// every splat below a node lies inside the node's box.
#pragma once

#include <cstdint>
#include <vector>

#include "render/render_scene.h"

namespace splatkit::render {

struct Box3 {
  Vec3f min{1, 1, 1}, max{0, 0, 0};  // empty when min.x > max.x
  bool empty() const { return min.x > max.x; }
  void extend(const Box3& b);
  void extend(const Vec3f& p);
  float area() const;  // surface area (0 when empty)
};

// Median: split at the median centre along the longest axis of the centres' box. Surface area
// heuristic (MacDonald and Booth 1990): of 16 bins per axis, the split of least
// area(left)·n(left) + area(right)·n(right).
enum class BvhSplit { kMedian, kSah };

struct ChunkBvhNode {
  Box3 box;
  uint32_t parent = UINT32_MAX;  // UINT32_MAX for the root
  uint32_t left = 0, right = 0;  // interior: children; leaf: left = first entry in order, right =
                                 // one past the last
  bool leaf = false;
  uint32_t depth = 0;  // root 0
  uint32_t size() const { return leaf ? right - left : 0; }
};

struct ChunkBvh {
  std::vector<ChunkBvhNode> nodes;  // root at 0, parents before children (median: pre-order)
  std::vector<uint32_t> order;      // #N splat indices; each leaf's range ascending
  uint32_t leaf_count = 0;
  uint32_t max_leaf = 0;
  double build_seconds = 0;
  // Sum over nodes of area(node) / area(root) (the SAH cost of traversing it, without leaves'
  // splat counts) and over leaves of size × area / area(root): lower is a better hierarchy.
  double sah_cost() const;
};

// Builds the hierarchy of a plain scene (positions, normals, radii; QSplat scenes are not
// supported: Error(kUsage)). leaf_size >= 1. Deterministic (independent of the thread count);
// the median hierarchy builds its large subtrees in parallel (TBB).
ChunkBvh build_chunk_bvh(const RenderScene& scene, uint32_t leaf_size = 4096,
                         BvhSplit split = BvhSplit::kMedian);

}  // namespace splatkit::render
