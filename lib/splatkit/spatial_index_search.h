// SpatialIndex's internals shared by its source files (spatial_index_*.cpp): the box distance
// bounds, the (squared distance, index) keys, the depth-first leaf walk and the single k-nearest
// search. Not part of the public API.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "splatkit/spatial_index.h"

namespace splatkit::spatial_index_detail {

inline constexpr float kInf = std::numeric_limits<float>::infinity();
inline constexpr uint32_t kInfBits = 0x7f800000;
// Batch queries are handed out in blocks of at most this many points (bounded scratch memory).
inline constexpr std::size_t kBlockSize = 1024;
// A leaf's shared candidate set (kNN and overlaps) holds at most this many points.
inline constexpr std::size_t kCandidateLimit = 512;

// Lower bound of the squared distance from q to any point in the box. Each term is computed like
// the point distance (a rounded difference, squared, summed x, y, z), and rounding is monotonic,
// so the bound never exceeds the float distance of a point inside: pruning with it is exact.
template <typename Box>
inline float box_sq_dist(const Box& b, float qx, float qy, float qz) {
  float dx = std::max(std::max(b.lo[0] - qx, qx - b.hi[0]), 0.0f);
  float dy = std::max(std::max(b.lo[1] - qy, qy - b.hi[1]), 0.0f);
  float dz = std::max(std::max(b.lo[2] - qz, qz - b.hi[2]), 0.0f);
  return dx * dx + dy * dy + dz * dz;
}

// For q inside the box: squared distance to its nearest face, a lower bound of the float
// distance of every point outside the box or on its surface, by the same argument.
template <typename Box>
inline float inner_margin_sq(const Box& b, float qx, float qy, float qz) {
  float m = std::min(
      {qx - b.lo[0], b.hi[0] - qx, qy - b.lo[1], b.hi[1] - qy, qz - b.lo[2], b.hi[2] - qz});
  return m * m;
}

// Lower bound of box_sq_dist(b, p) for every point p in box a: per axis, the gap between the
// boxes, rounded like the point's term (monotonic rounding again), so pruning nodes with it never
// drops a point the per-point test would keep.
template <typename Box>
inline float box_gap_sq(const Box& a, const Box& b) {
  float dx = std::max(std::max(a.lo[0] - b.hi[0], b.lo[0] - a.hi[0]), 0.0f);
  float dy = std::max(std::max(a.lo[1] - b.hi[1], b.lo[1] - a.hi[1]), 0.0f);
  float dz = std::max(std::max(a.lo[2] - b.hi[2], b.lo[2] - a.hi[2]), 0.0f);
  return dx * dx + dy * dy + dz * dz;
}

inline bool is_finite(const Vec3f& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

inline bool before(float d_a, uint32_t id_a, float d_b, uint32_t id_b) {
  return d_a < d_b || (d_a == d_b && id_a < id_b);
}

// A candidate as one integer: the bits of a non-negative float order like its value, so
// (squared distance, index) compares as a single uint64_t and the insertion loop stays tight.
inline uint64_t make_key(float d2, uint32_t id) {
  return uint64_t{std::bit_cast<uint32_t>(d2)} << 32 | id;
}
inline uint32_t key_bits(uint64_t key) { return static_cast<uint32_t>(key >> 32); }
inline float key_d2(uint64_t key) { return std::bit_cast<float>(key_bits(key)); }
inline uint32_t key_id(uint64_t key) { return static_cast<uint32_t>(key); }
// The distance part of a bound key as a float; +inf for the "no bound yet" key ~0.
inline float key_d2_or_inf(uint64_t key) {
  return std::bit_cast<float>(std::min(key_bits(key), kInfBits));
}

}  // namespace splatkit::spatial_index_detail

namespace splatkit {

// (This header is included only by SpatialIndex's own sources.)
using namespace spatial_index_detail;

template <class Far, class Leaf>
bool SpatialIndex::visit_leaves(uint32_t root, Far&& far, Leaf&& leaf) const {
  uint32_t stack[64];  // at most one pending node per level, plus one
  int top = 0;
  stack[top++] = root;
  while (top > 0) {
    const uint32_t node = stack[--top];
    if (far(node)) continue;
    if (node < first_leaf_) {
      stack[top++] = 2 * node + 2;
      stack[top++] = 2 * node + 1;
    } else if (!leaf(node - first_leaf_)) {
      return false;
    }
  }
  return true;
}

// The k best candidates so far, sorted: a fixed-size insertion array, which beats a heap for the
// small k of normal estimation. `cap` rejects candidates beyond a distance already known to hold
// k points (a warm start from the previous query); ~0 when nothing is known.
struct SpatialIndex::KnnState {
  KnnState(std::size_t k_, uint64_t* keys_, uint64_t cap_ = ~uint64_t{0})
      : k(k_), keys(keys_), cap(cap_), worst(cap_) {}

  std::size_t k;
  uint64_t* keys;
  uint64_t cap;
  uint64_t worst;  // a candidate must be smaller to enter: cap until full, then keys[k - 1]
  std::size_t count = 0;

  // Precondition: key < worst. The first k candidates are appended and sorted once, which costs
  // less than k insertions into a growing sorted array.
  void insert(uint64_t key) {
    if (count < k) {
      keys[count++] = key;
      if (count == k) {
        std::sort(keys, keys + k);
        worst = keys[k - 1];
      }
      return;
    }
    std::size_t pos = k - 1;
    while (pos > 0 && key < keys[pos - 1]) {
      keys[pos] = keys[pos - 1];
      --pos;
    }
    keys[pos] = key;
    worst = keys[k - 1];
  }
  // Sorts a result that never filled up (fewer than k points within reach).
  void finish() {
    if (count < k) std::sort(keys, keys + count);
  }
};

// One k-nearest query: depth-first, nearer child first, pruning every box farther than the
// current k-th candidate. A box exactly as far as the k-th candidate is still visited: it may hold
// a tie with a smaller index. Box distances are compared by their bits, like the keys.
struct SpatialIndex::KnnSearch {
  const SpatialIndex& index;
  float qx, qy, qz;
  uint32_t skip_position;  // the query itself in batches (kNone: none)
  KnnState& state;
  bool sse2;  // scan leaves four points at a time (simd_level() >= kSse2)

  uint32_t box_bits(uint32_t node) const {
    return std::bit_cast<uint32_t>(box_sq_dist(index.boxes_[node], qx, qy, qz));
  }

  void offer(uint32_t p, float d2) {
    uint64_t key = make_key(d2, index.ids_[p]);
    if (key < state.worst && p != skip_position) state.insert(key);
  }

  // Offers the points of a visited leaf that are not farther than the k-th candidate.
  void scan_leaf(uint32_t leaf) {
    const uint32_t begin = index.leaf_start_[leaf], end = index.leaf_start_[leaf + 1];
#if defined(__SSE2__)
    if (sse2) return scan_leaf_sse2(begin, end);
#endif
    for (uint32_t p = begin; p < end; ++p) {
      float dx = index.xs_[p] - qx, dy = index.ys_[p] - qy, dz = index.zs_[p] - qz;
      float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 <= key_d2_or_inf(state.worst)) offer(p, d2);
    }
  }

#if defined(__SSE2__)
  // Most points of a visited leaf are farther than the k-th candidate: compare four at a time and
  // branch only on the few that pass. The lanes compute exactly the scalar expression.
  void scan_leaf_sse2(uint32_t begin, uint32_t end) {
    const __m128 vqx = _mm_set1_ps(qx), vqy = _mm_set1_ps(qy), vqz = _mm_set1_ps(qz);
    __m128 bound = _mm_set1_ps(key_d2_or_inf(state.worst));
    for (std::size_t p = begin; p < end; p += 4) {
      __m128 dx = _mm_sub_ps(_mm_loadu_ps(index.xs_.data() + p), vqx);
      __m128 dy = _mm_sub_ps(_mm_loadu_ps(index.ys_.data() + p), vqy);
      __m128 dz = _mm_sub_ps(_mm_loadu_ps(index.zs_.data() + p), vqz);
      __m128 d2 =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
      int mask = _mm_movemask_ps(_mm_cmple_ps(d2, bound));
      if (end - p < 4) mask &= (1 << (end - p)) - 1;  // lanes past the leaf (padding or next leaf)
      if (mask == 0) continue;
      alignas(16) float lanes[4];
      _mm_store_ps(lanes, d2);
      for (; mask != 0; mask &= mask - 1) {
        int lane = std::countr_zero(static_cast<unsigned>(mask));
        offer(p + lane, lanes[lane]);
      }
      bound = _mm_set1_ps(key_d2_or_inf(state.worst));
    }
  }
#endif

  // Searches the subtree `node`, whose box distance is node_bits.
  void descend(uint32_t node, uint32_t node_bits) {
    struct Pending {
      uint32_t node;
      uint32_t d2_bits;
    };
    Pending stack[64];
    int top = 0;
    const uint32_t first_leaf = index.first_leaf_;
    for (;;) {
      if (node_bits <= key_bits(state.worst)) {
        while (node < first_leaf) {
          uint32_t near = 2 * node + 1, far = near + 1;
          uint32_t near_bits = box_bits(near), far_bits = box_bits(far);
          if (far_bits < near_bits) {
            std::swap(near, far);
            std::swap(near_bits, far_bits);
          }
          uint32_t bound = key_bits(state.worst);
          if (far_bits <= bound) stack[top++] = {far, far_bits};
          if (near_bits > bound) break;
          node = near;
        }
        if (node >= first_leaf) scan_leaf(node - first_leaf);
      }
      if (top == 0) return;
      --top;
      node = stack[top].node;
      node_bits = stack[top].d2_bits;
    }
  }

  void from_root() { descend(0, box_bits(0)); }

  // Squared distance (as bits) from q, inside the node's box, to the box's nearest face. Every
  // point outside the node is outside or on the face of its tight box (cells meet only on split
  // planes), so its float distance is at least this: the same monotonic-rounding argument as
  // box_sq_dist.
  uint32_t inner_margin_bits(uint32_t node) const {
    return std::bit_cast<uint32_t>(inner_margin_sq(index.boxes_[node], qx, qy, qz));
  }

  // For a query inside leaf `leaf`: that leaf first (the best first candidates), then the
  // sibling of each node on the way up, until the k-th candidate is nearer than every face of
  // the node reached (nothing outside it can then compete). This covers the tree once and skips
  // the descent from the root.
  void from_leaf(uint32_t leaf) {
    scan_leaf(leaf);
    for (uint32_t node = index.first_leaf_ + leaf; node > 0; node = (node - 1) / 2) {
      if (inner_margin_bits(node) > key_bits(state.worst)) return;
      uint32_t sibling = (node & 1) ? node + 1 : node - 1;
      descend(sibling, box_bits(sibling));
    }
  }
};

}  // namespace splatkit
