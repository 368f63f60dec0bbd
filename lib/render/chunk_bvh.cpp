#include "render/chunk_bvh.h"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "render/setup_splats.h"
#include "splatkit/error.h"
#include "splatkit/seconds_since.h"
#include "splatkit/select_rank.h"
#include "splatkit/slot_array.h"

namespace splatkit::render {

void Box3::extend(const Box3& b) {
  if (b.empty()) return;
  if (empty()) {
    *this = b;
    return;
  }
  min = {std::min(min.x, b.min.x), std::min(min.y, b.min.y), std::min(min.z, b.min.z)};
  max = {std::max(max.x, b.max.x), std::max(max.y, b.max.y), std::max(max.z, b.max.z)};
}

void Box3::extend(const Vec3f& p) { extend(Box3{p, p}); }

float Box3::area() const {
  if (empty()) return 0;
  const Vec3f d = max - min;
  return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

namespace {

inline float axis(const Vec3f& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

Box3 splat_box(const RenderScene& s, std::size_t i) {
  const Vec3f c = s.positions[i], n = s.normals[i];
  // With the ring the renderer may draw around a splat (setup_splats.h).
  const float r = s.radii[i] * kRingScale;
  Vec3f h{r, r, r};
  if (s.axes.empty()) {
    auto ext = [&](float ni) { return r * std::sqrt(std::max(0.0f, 1.0f - ni * ni)); };
    // A little more than the exact extent: the disc's arithmetic is in float.
    h = Vec3f{ext(n.x), ext(n.y), ext(n.z)} * 1.0001f + Vec3f{r, r, r} * 1e-4f;
  }
  return {c - h, c + h};
}

struct Builder {
  const RenderScene& scene;
  uint32_t leaf_size;
  BvhSplit split;
  std::vector<Box3> boxes;  // per splat (the surface area heuristic's bins)
  ChunkBvh bvh;

  Box3 range_box(uint32_t b, uint32_t e) const {
    if (b == e) return {};
    const Box3 first = splat_box(scene, bvh.order[b]);
    Vec3f lo = first.min, hi = first.max;
    for (uint32_t i = b + 1; i < e; ++i) {
      const Box3 x = splat_box(scene, bvh.order[i]);
      lo = {std::min(lo.x, x.min.x), std::min(lo.y, x.min.y), std::min(lo.z, x.min.z)};
      hi = {std::max(hi.x, x.max.x), std::max(hi.y, x.max.y), std::max(hi.z, x.max.z)};
    }
    return {lo, hi};
  }

  // The split position in [b, e) (b < m < e), with the range partitioned.
  uint32_t median_split(uint32_t b, uint32_t e, int ax) {
    const uint32_t m = b + (e - b) / 2;
    auto key = [&](uint32_t i) { return std::make_pair(axis(scene.positions[i], ax), i); };
    std::nth_element(bvh.order.begin() + b, bvh.order.begin() + m, bvh.order.begin() + e,
                     [&](uint32_t x, uint32_t y) { return key(x) < key(y); });
    return m;
  }

  uint32_t sah_split(uint32_t b, uint32_t e, const Box3& centres) {
    constexpr int kBins = 16;
    float best = INFINITY;
    int best_bin = -1, best_axis = -1;
    for (int ax = 0; ax < 3; ++ax) {
      const float lo = axis(centres.min, ax), hi = axis(centres.max, ax);
      if (!(hi > lo)) continue;
      const float scale = kBins / (hi - lo);
      std::array<Box3, kBins> bin_box;
      std::array<uint32_t, kBins> bin_n{};
      for (uint32_t i = b; i < e; ++i) {
        const uint32_t s = bvh.order[i];
        const int k = std::min(kBins - 1, int((axis(scene.positions[s], ax) - lo) * scale));
        bin_box[k].extend(boxes[s]);
        ++bin_n[k];
      }
      std::array<float, kBins> right_cost{};
      Box3 acc;
      uint32_t n = 0;
      for (int k = kBins - 1; k > 0; --k) {
        acc.extend(bin_box[k]);
        n += bin_n[k];
        right_cost[k] = acc.area() * n;
      }
      acc = Box3{};
      n = 0;
      for (int k = 0; k + 1 < kBins; ++k) {
        acc.extend(bin_box[k]);
        n += bin_n[k];
        if (n == 0 || n == e - b) continue;
        const float cost = acc.area() * n + right_cost[k + 1];
        if (cost < best) {
          best = cost;
          best_bin = k;
          best_axis = ax;
        }
      }
    }
    if (best_axis < 0) return b;
    const float lo = axis(centres.min, best_axis), hi = axis(centres.max, best_axis);
    const float scale = kBins / (hi - lo);
    auto mid = std::stable_partition(bvh.order.begin() + b, bvh.order.begin() + e, [&](uint32_t s) {
      return std::min(kBins - 1, int((axis(scene.positions[s], best_axis) - lo) * scale)) <=
             best_bin;
    });
    return uint32_t(mid - bvh.order.begin());
  }

  void build(uint32_t node, uint32_t b, uint32_t e) {
    if (e - b <= leaf_size) {
      bvh.nodes[node].box = range_box(b, e);
      ChunkBvhNode& n = bvh.nodes[node];
      n.leaf = true;
      n.left = b;
      n.right = e;
      std::sort(bvh.order.begin() + b, bvh.order.begin() + e);
      ++bvh.leaf_count;
      bvh.max_leaf = std::max(bvh.max_leaf, e - b);
      return;
    }
    Vec3f lo = scene.positions[bvh.order[b]], hi = lo;
    for (uint32_t i = b + 1; i < e; ++i) {
      const Vec3f p = scene.positions[bvh.order[i]];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const Box3 centres{lo, hi};
    uint32_t m = split == BvhSplit::kSah ? sah_split(b, e, centres) : b;
    if (m <= b || m >= e) m = median_split(b, e, longest_axis(lo, hi));
    const uint32_t left = uint32_t(bvh.nodes.size());
    bvh.nodes.resize(bvh.nodes.size() + 2);
    for (uint32_t c : {left, left + 1}) {
      bvh.nodes[c].parent = node;
      bvh.nodes[c].depth = bvh.nodes[node].depth + 1;
    }
    bvh.nodes[node].left = left;
    bvh.nodes[node].right = left + 1;
    build(left, b, m);
    build(left + 1, m, e);
    Box3 box = bvh.nodes[left].box;
    box.extend(bvh.nodes[left + 1].box);
    bvh.nodes[node].box = box;
  }
};

// Nodes of the median hierarchy over `n` splats (its shape depends on n alone).
uint32_t median_nodes(uint32_t n, uint32_t leaf_size) {
  if (n <= leaf_size) return 1;
  return 1 + median_nodes(n / 2, leaf_size) + median_nodes(n - n / 2, leaf_size);
}

// The median hierarchy in pre-order (a node's left child right after it, its right child after
// the left subtree), so that subtrees are built in parallel into slots known in advance. The
// splats' centres travel with their indices (`pts`), so that the cuts read no position at
// random; a leaf's range of `order` takes its indices, ascending.
void build_median(Builder& bld, RankedPoint* pts, uint32_t node, uint32_t parent, uint32_t depth,
                  uint32_t b, uint32_t e) {
  ChunkBvh& bvh = bld.bvh;
  ChunkBvhNode& n = bvh.nodes[node];
  n.parent = parent;
  n.depth = depth;
  if (e - b <= bld.leaf_size) {
    for (uint32_t i = b; i < e; ++i) bvh.order[i] = pts[i].index();
    std::sort(bvh.order.begin() + b, bvh.order.begin() + e);
    n.box = bld.range_box(b, e);
    n.leaf = true;
    n.left = b;
    n.right = e;
    return;
  }
  Vec3f lo, hi;
  point_bounds(pts + b, pts + e, lo, hi);
  const uint32_t m = b + (e - b) / 2;
  select_rank(pts + b, pts + m, pts + e, longest_axis(lo, hi));
  const uint32_t left = node + 1, right = left + median_nodes(m - b, bld.leaf_size);
  n.left = left;
  n.right = right;
  auto l = [&] { build_median(bld, pts, left, node, depth + 1, b, m); };
  auto r = [&] { build_median(bld, pts, right, node, depth + 1, m, e); };
  if (e - b > (1u << 16))
    tbb::parallel_invoke(l, r);
  else {
    l();
    r();
  }
  Box3 box = bvh.nodes[left].box;
  box.extend(bvh.nodes[right].box);
  bvh.nodes[node].box = box;
}

}  // namespace

double ChunkBvh::sah_cost() const {
  if (nodes.empty()) return 0;
  const double root = std::max(1e-30f, nodes[0].box.area());
  double cost = 0;
  for (const ChunkBvhNode& n : nodes) cost += n.box.area() / root * (n.leaf ? 1.0 + n.size() : 1.0);
  return cost;
}

ChunkBvh build_chunk_bvh(const RenderScene& scene, uint32_t leaf_size, BvhSplit split) {
  if (scene.qsplat) throw_usage("occlusion culling needs a plain splat scene, not a QSplat file");
  if (leaf_size < 1) throw_usage("BVH leaves need at least one splat");
  const auto t0 = Clock::now();
  Builder b{scene, leaf_size, split, {}, {}};
  const std::size_t n = scene.size();
  if (n >= UINT32_MAX) throw_usage("too many splats for the chunk hierarchy (2^32)");
  b.bvh.order.resize(n);
  if (split == BvhSplit::kMedian) {
    SlotArray<RankedPoint> pts;  // uninitialised: filled below, its pages faulted in parallel
    pts.allocate(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i)
        pts[i] = RankedPoint::make(scene.positions[i], uint32_t(i));
    });
    b.bvh.nodes.resize(median_nodes(uint32_t(n), leaf_size));
    build_median(b, pts.get(), 0, UINT32_MAX, 0, 0, uint32_t(n));
    for (const ChunkBvhNode& x : b.bvh.nodes)
      if (x.leaf) {
        ++b.bvh.leaf_count;
        b.bvh.max_leaf = std::max(b.bvh.max_leaf, x.size());
      }
  } else {
    b.boxes.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) b.boxes[i] = splat_box(scene, i);
    });
    for (std::size_t i = 0; i < n; ++i) b.bvh.order[i] = uint32_t(i);
    b.bvh.nodes.reserve(2 * (n / std::max<uint32_t>(1, leaf_size / 2) + 1));
    b.bvh.nodes.resize(1);
    b.build(0, 0, uint32_t(n));
  }
  b.bvh.build_seconds = seconds_since(t0);
  return std::move(b.bvh);
}

}  // namespace splatkit::render
