#include "splatkit/spatial_index.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "splatkit/error.h"
#include "splatkit/lane_compress.h"
#include "splatkit/rank_sort_avx2.h"

namespace splatkit {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t kInfBits = 0x7f800000;
// Batch queries are handed out in blocks of at most this many points (bounded scratch memory).
constexpr std::size_t kBlockSize = 1024;
// A leaf's shared candidate set reaches this factor times the previous leaf's largest k-th
// squared distance, and holds at most kCandidateLimit points.
constexpr float kGuessGrowth = 1.1f;
constexpr std::size_t kCandidateLimit = 512;
// rank_avx2 counts ranks for up to this many candidates within the cap (quadratic), and sorts
// beyond.
constexpr std::size_t kRankLimit = 160;
// Points per task when copying into and out of the build array.
constexpr std::size_t kCopyGrain = 65536;
// Below this many points a subtree is built on the current thread.
constexpr std::size_t kParallelBuildCutoff = 32768;

struct BuildPoint {
  float c[3];
  uint32_t id;
};

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

// Moves the points whose coordinate `axis` passes `take` to the front of [first, last), in one
// pass without data-dependent branches (a Lomuto partition that always swaps); returns the end
// of the front part.
template <typename Take>
BuildPoint* partition_points(BuildPoint* first, BuildPoint* last, int axis, Take take) {
  BuildPoint* out = first;
  for (BuildPoint* it = first; it != last; ++it) {
    const BuildPoint v = *it;
    *it = *out;
    *out = v;
    out += take(v.c[axis]) ? 1 : 0;
  }
  return out;
}

// std::nth_element by coordinate `axis` (the same contract) with the branch-free partition above
// and a median-of-three pivot. When the pivot is the smallest coordinate its copies are split off
// instead, so runs of equal coordinates still make progress; after a generous number of rounds
// (an adversarial input) it hands over to std::nth_element.
void select_nth(BuildPoint* first, BuildPoint* nth, BuildPoint* last, int axis) {
  auto less = [axis](const BuildPoint& a, const BuildPoint& b) { return a.c[axis] < b.c[axis]; };
  int rounds = 2 * std::bit_width(static_cast<std::size_t>(last - first)) + 8;
  while (last - first > 16) {
    if (rounds-- == 0) return std::nth_element(first, nth, last, less);
    float a = first->c[axis], b = first[(last - first) / 2].c[axis], c = last[-1].c[axis];
    const float pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
    BuildPoint* below = partition_points(first, last, axis, [pivot](float v) { return v < pivot; });
    if (nth < below) {
      last = below;
      continue;
    }
    if (below > first) {
      first = below;
      continue;
    }
    // The pivot is the smallest coordinate: split off its copies (at least one) instead.
    BuildPoint* equal =
        partition_points(first, last, axis, [pivot](float v) { return v == pivot; });
    if (nth < equal) return;
    first = equal;
  }
  std::sort(first, last, less);
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

}  // namespace

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

// Builds the subtree `node` over pts[begin, end): tight box, then a median split on its widest
// axis at the position where the implicit layout puts the boundary between its two halves.
struct SpatialIndex::Builder {
  std::vector<BuildPoint>& pts;
  std::vector<Box>& boxes;
  const std::vector<uint32_t>& leaf_start;
  uint32_t first_leaf;

  void build(uint32_t node, uint32_t leaf_lo, uint32_t leaf_hi) {
    std::size_t begin = leaf_start[leaf_lo], end = leaf_start[leaf_hi];
    Box box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
    for (std::size_t i = begin; i < end; ++i) {
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = std::min(box.lo[a], pts[i].c[a]);
        box.hi[a] = std::max(box.hi[a], pts[i].c[a]);
      }
    }
    boxes[node] = box;
    if (node >= first_leaf) return;

    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
    }
    uint32_t leaf_mid = leaf_lo + (leaf_hi - leaf_lo) / 2;
    std::size_t mid = leaf_start[leaf_mid];
    select_nth(pts.data() + begin, pts.data() + mid, pts.data() + end, axis);
    auto left = [&] { build(2 * node + 1, leaf_lo, leaf_mid); };
    auto right = [&] { build(2 * node + 2, leaf_mid, leaf_hi); };
    if (end - begin >= kParallelBuildCutoff) {
      tbb::parallel_invoke(left, right);
    } else {
      left();
      right();
    }
  }
};

SpatialIndex::SpatialIndex(std::span<const Vec3f> points, std::size_t max_leaf_size) {
  if (max_leaf_size == 0) throw std::invalid_argument("SpatialIndex: max_leaf_size must be > 0");
  if (points.size() > std::size_t{kNone} - 1) {
    throw std::invalid_argument("SpatialIndex: more than 2^32 - 2 points");
  }
  const std::size_t n = points.size();
  std::vector<BuildPoint> pts(n);
  std::atomic<bool> all_finite{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kCopyGrain), [&](const auto& r) {
    bool finite = true;
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const Vec3f& p = points[i];
      finite &= is_finite(p);
      pts[i] = {{p.x, p.y, p.z}, static_cast<uint32_t>(i)};
    }
    if (!finite) all_finite = false;
  });
  if (!all_finite) {
    const std::size_t i = static_cast<std::size_t>(
        std::find_if_not(points.begin(), points.end(), is_finite) - points.begin());
    throw Error(ErrorKind::kBadInput,
                "spatial index: point " + std::to_string(i) + " has a non-finite coordinate");
  }

  // 2^depth leaves of equal size (within one point), so the layout needs no pointers.
  uint32_t leaves = 1;
  while (n > std::size_t{leaves} * max_leaf_size) leaves *= 2;
  first_leaf_ = leaves - 1;
  leaf_start_.resize(leaves + 1);
  for (uint32_t j = 0; j <= leaves; ++j)
    leaf_start_[j] = static_cast<uint32_t>(uint64_t{j} * n / leaves);
  boxes_.resize(2 * std::size_t{leaves} - 1);
  Builder{pts, boxes_, leaf_start_, first_leaf_}.build(0, 0, leaves);

  // Padded by three so that four-wide loads at the end of the last leaf stay in bounds.
  xs_.assign(n + 3, 0.0f);
  ys_.assign(n + 3, 0.0f);
  zs_.assign(n + 3, 0.0f);
  ids_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kCopyGrain), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      xs_[i] = pts[i].c[0];
      ys_[i] = pts[i].c[1];
      zs_[i] = pts[i].c[2];
      ids_[i] = pts[i].id;
    }
  });
}

std::size_t SpatialIndex::memory_bytes() const {
  return (xs_.capacity() + ys_.capacity() + zs_.capacity()) * sizeof(float) +
         ids_.capacity() * sizeof(uint32_t) + boxes_.capacity() * sizeof(Box) +
         leaf_start_.capacity() * sizeof(uint32_t);
}

// One k-nearest query: depth-first, nearer child first, pruning every box farther than the
// current k-th candidate. A box exactly as far as the k-th candidate is still visited: it may hold
// a tie with a smaller index. Box distances are compared by their bits, like the keys.
struct SpatialIndex::KnnSearch {
  const SpatialIndex& index;
  float qx, qy, qz;
  uint32_t skip_position;  // the query itself in batches (kNone: none)
  KnnState& state;

  uint32_t box_bits(uint32_t node) const {
    return std::bit_cast<uint32_t>(box_sq_dist(index.boxes_[node], qx, qy, qz));
  }

  void offer(uint32_t p, float d2) {
    uint64_t key = make_key(d2, index.ids_[p]);
    if (key < state.worst && p != skip_position) state.insert(key);
  }

  // Most points of a visited leaf are farther than the k-th candidate: compare four at a time and
  // branch only on the few that pass. The lanes compute exactly the scalar expression.
  void scan_leaf(uint32_t leaf) {
    const uint32_t begin = index.leaf_start_[leaf], end = index.leaf_start_[leaf + 1];
#if defined(__SSE2__)
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
#else
    for (uint32_t p = begin; p < end; ++p) {
      float dx = index.xs_[p] - qx, dy = index.ys_[p] - qy, dz = index.zs_[p] - qz;
      float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 <= key_d2_or_inf(state.worst)) offer(p, d2);
    }
#endif
  }

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

std::size_t SpatialIndex::knn(const Vec3f& q, std::size_t k, uint32_t* out_indices,
                              float* out_sq_dists) const {
  k = std::min(k, size());
  if (k == 0 || !is_finite(q)) return 0;
  std::vector<uint64_t> keys(k);
  KnnState state(k, keys.data());
  KnnSearch{*this, q.x, q.y, q.z, kNone, state}.from_root();
  state.finish();
  for (std::size_t c = 0; c < state.count; ++c) {
    out_indices[c] = key_id(keys[c]);
    if (out_sq_dists != nullptr) out_sq_dists[c] = key_d2(keys[c]);
  }
  return state.count;
}

// The queries of one leaf share one candidate set: every point whose box distance to the leaf's
// box is at most a guessed reach R (squared: reach2). For a query q in the box, every point left
// out has a float distance > reach2 (box_sq_dist is a lower bound, as above), so if q finds its
// k - 1 nearest among the candidates within reach2, that answer is exact, ties included. A query
// that finds fewer (its k-th neighbour lies beyond the guess) is answered by the ordinary search.
// The guess comes from the previous leaf's farthest k-th neighbour: neighbouring leaves have
// similar densities, so few queries fall back.
struct SpatialIndex::LeafBatch {
  const SpatialIndex& index;
  std::vector<float> cx, cy, cz;  // candidates' coordinates, padded with NaN to a multiple of 8
  std::vector<uint32_t> cid;      // their original indices
  std::size_t size = 0;           // candidates plus padding
  std::vector<uint64_t> skeys;    // rank_avx2's scratch: the candidates within the cap

  // Collects the candidates for `leaf` within reach2; false when there would be more than
  // `limit` of them (a sparse region or a very uneven leaf: the per-query search is cheaper).
  bool gather(uint32_t leaf, float reach2, std::size_t limit, bool avx2) {
    const Box& b = index.boxes_[index.first_leaf_ + leaf];
    // A leaf may push the count past the limit by its size, and the packing stores write eight.
    const std::size_t room = limit + index.leaf_start_[1] + 1 + 16;
    if (cx.size() < room) {
      cx.resize(room), cy.resize(room), cz.resize(room), cid.resize(room);
      skeys.resize(room + 8);
    }
    std::size_t count = 0;
    const bool within = index.visit_leaves(
        0, [&](uint32_t node) { return box_gap_sq(index.boxes_[node], b) > reach2; },
        [&](uint32_t l) {
          if (count > limit) return false;
#if defined(__x86_64__)
          if (avx2) {
            count = gather_leaf_avx2(l, b, reach2, count);
            return true;
          }
#endif
          for (uint32_t p = index.leaf_start_[l]; p < index.leaf_start_[l + 1]; ++p) {
            const float x = index.xs_[p], y = index.ys_[p], z = index.zs_[p];
            cx[count] = x, cy[count] = y, cz[count] = z, cid[count] = index.ids_[p];
            count += box_sq_dist(b, x, y, z) <= reach2;
          }
          return true;
        });
    if (!within || count > limit) return false;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t j = count; j % 8 != 0; ++j) cx[j] = cy[j] = cz[j] = nan;
    size = (count + 7) & ~std::size_t{7};
    return true;
  }

#if defined(__x86_64__)
  // gather's per-point test for one leaf, eight points at a time (box_sq_dist lane by lane, the
  // same float operations), the passing points packed to the end of the candidate arrays.
  __attribute__((target("avx2"))) std::size_t gather_leaf_avx2(uint32_t l, const Box& b,
                                                               float reach2, std::size_t count) {
    const __m256 lo_x = _mm256_set1_ps(b.lo[0]), lo_y = _mm256_set1_ps(b.lo[1]),
                 lo_z = _mm256_set1_ps(b.lo[2]), hi_x = _mm256_set1_ps(b.hi[0]),
                 hi_y = _mm256_set1_ps(b.hi[1]), hi_z = _mm256_set1_ps(b.hi[2]),
                 bound = _mm256_set1_ps(reach2), zero = _mm256_setzero_ps();
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const uint32_t end = index.leaf_start_[l + 1];
    for (std::size_t p = index.leaf_start_[l]; p < end; p += 8) {
      const __m256i valid = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(end - p)), lanes);
      const __m256 x = _mm256_maskload_ps(index.xs_.data() + p, valid);
      const __m256 y = _mm256_maskload_ps(index.ys_.data() + p, valid);
      const __m256 z = _mm256_maskload_ps(index.zs_.data() + p, valid);
      const __m256i ids =
          _mm256_maskload_epi32(reinterpret_cast<const int*>(index.ids_.data() + p), valid);
      const __m256 dx =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lo_x, x), _mm256_sub_ps(x, hi_x)), zero);
      const __m256 dy =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lo_y, y), _mm256_sub_ps(y, hi_y)), zero);
      const __m256 dz =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lo_z, z), _mm256_sub_ps(z, hi_z)), zero);
      const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                      _mm256_mul_ps(dz, dz));
      const unsigned mask =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(d2, bound, _CMP_LE_OQ))) &
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(valid)));
      const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(kLaneCompress[mask]));
      _mm256_storeu_ps(cx.data() + count, _mm256_permutevar8x32_ps(x, perm));
      _mm256_storeu_ps(cy.data() + count, _mm256_permutevar8x32_ps(y, perm));
      _mm256_storeu_ps(cz.data() + count, _mm256_permutevar8x32_ps(z, perm));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(cid.data() + count),
                          _mm256_permutevar8x32_epi32(ids, perm));
      count += static_cast<std::size_t>(std::popcount(mask));
    }
    return count;
  }
#endif

#if defined(__x86_64__)
  // The k - 1 nearest candidates (squared distance <= cap) of the point at tree position p other
  // than itself, sorted, into keys (which has room for k: the last is scratch); false when fewer
  // than k - 1 lie within the cap. Without data-dependent branches: the candidates within the cap
  // are packed eight at a time, then each one's rank in the (squared distance, index) order is
  // counted against all the others and the first k - 1 ranks are written in place. NaN padding
  // never passes a comparison.
  __attribute__((target("avx2"))) bool rank_avx2(uint32_t p, float cap, std::size_t others,
                                                 uint64_t* keys) {
    const __m256 vqx = _mm256_set1_ps(index.xs_[p]), vqy = _mm256_set1_ps(index.ys_[p]),
                 vqz = _mm256_set1_ps(index.zs_[p]), bound = _mm256_set1_ps(cap);
    const __m256i self = _mm256_set1_epi32(static_cast<int>(index.ids_[p]));
    std::size_t m = 0;
    for (std::size_t j = 0; j < size; j += 8) {
      __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(cx.data() + j), vqx);
      __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(cy.data() + j), vqy);
      __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(cz.data() + j), vqz);
      __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                _mm256_mul_ps(dz, dz));
      __m256i ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(cid.data() + j));
      const unsigned mask =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(d2, bound, _CMP_LE_OQ))) &
          ~static_cast<unsigned>(
              _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(ids, self))));
      // Packed, then paired into keys (index low, distance bits high) in lane order.
      const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(kLaneCompress[mask]));
      const __m256i packed_d2 = _mm256_castps_si256(_mm256_permutevar8x32_ps(d2, perm));
      const __m256i packed_ids = _mm256_permutevar8x32_epi32(ids, perm);
      const __m256i lo = _mm256_unpacklo_epi32(packed_ids, packed_d2);  // lanes 0, 1, 4, 5
      const __m256i hi = _mm256_unpackhi_epi32(packed_ids, packed_d2);  // lanes 2, 3, 6, 7
      auto* out = reinterpret_cast<__m256i*>(skeys.data() + m);
      _mm256_storeu_si256(out, _mm256_permute2x128_si256(lo, hi, 0x20));
      _mm256_storeu_si256(out + 1, _mm256_permute2x128_si256(lo, hi, 0x31));
      m += static_cast<std::size_t>(std::popcount(mask));
    }
    if (m < others) return false;
    if (m > kRankLimit) {
      std::partial_sort(skeys.begin(), skeys.begin() + others, skeys.begin() + m);
      std::copy_n(skeys.begin(), others, keys);
      return true;
    }
    // Keys are below 2^63 (non-negative distances), so the signed comparison orders them.
    for (std::size_t i0 = 0; i0 < m; i0 += 4) {
      const __m256i ki = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(skeys.data() + i0));
      __m256i rank = _mm256_setzero_si256();
      for (std::size_t j = 0; j < m; ++j) {
        const __m256i kj = _mm256_set1_epi64x(static_cast<long long>(skeys[j]));
        rank = _mm256_sub_epi64(rank, _mm256_cmpgt_epi64(ki, kj));
      }
      alignas(32) uint64_t ranks[4];
      _mm256_store_si256(reinterpret_cast<__m256i*>(ranks), rank);
      // Without branches: ranks past k - 2 and lanes past m go to the spare slot keys[others].
      for (std::size_t lane = 0; lane < 4; ++lane) {
        const uint64_t rank_or_spare = i0 + lane < m ? ranks[lane] : others;
        keys[std::min<uint64_t>(rank_or_spare, others)] = skeys[i0 + lane];
      }
    }
    return true;
  }
#endif

  // The portable path of rank_avx2, the same answer: a cap-filtered insertion, four lanes at a
  // time where SSE2 is available.
  bool query(uint32_t p, float cap, std::size_t others, uint64_t* keys) const {
    KnnState state(others, keys, make_key(cap, kNone));
    const uint32_t self = index.ids_[p];
#if defined(__SSE2__)
    const __m128 vqx = _mm_set1_ps(index.xs_[p]), vqy = _mm_set1_ps(index.ys_[p]),
                 vqz = _mm_set1_ps(index.zs_[p]);
    __m128 bound = _mm_set1_ps(cap);
    for (std::size_t j = 0; j < size; j += 4) {
      __m128 dx = _mm_sub_ps(_mm_loadu_ps(cx.data() + j), vqx);
      __m128 dy = _mm_sub_ps(_mm_loadu_ps(cy.data() + j), vqy);
      __m128 dz = _mm_sub_ps(_mm_loadu_ps(cz.data() + j), vqz);
      __m128 d2 =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
      int mask = _mm_movemask_ps(_mm_cmple_ps(d2, bound));
      if (mask == 0) continue;
      alignas(16) float lanes[4];
      _mm_store_ps(lanes, d2);
      for (; mask != 0; mask &= mask - 1) {
        const int lane = std::countr_zero(static_cast<unsigned>(mask));
        const uint32_t id = cid[j + lane];
        const uint64_t key = make_key(lanes[lane], id);
        if (key < state.worst && id != self) state.insert(key);
      }
      bound = _mm_set1_ps(key_d2_or_inf(state.worst));
    }
#else
    const float qx = index.xs_[p], qy = index.ys_[p], qz = index.zs_[p];
    for (std::size_t j = 0; j < size; ++j) {
      const float dx = cx[j] - qx, dy = cy[j] - qy, dz = cz[j] - qz;
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (!(d2 <= key_d2_or_inf(state.worst))) continue;
      const uint64_t key = make_key(d2, cid[j]);
      if (key < state.worst && cid[j] != self) state.insert(key);
    }
#endif
    return state.count == others;
  }
};

// Rows for the points at tree positions [begin, end), written consecutively (row r for position
// begin + r), each laid out as documented for knn_all. Leaf by leaf: a shared candidate set
// (LeafBatch) answers most queries; the rest, and the first query of a range (which seeds the
// guess), use the ordinary search from their own leaf.
void SpatialIndex::knn_rows(std::size_t begin, std::size_t end, std::size_t k, uint32_t* indices,
                            float* sq_dists) const {
  const std::size_t others = std::min(k - 1, size() - 1);
  std::vector<uint64_t> keys(others + 1);
  LeafBatch batch{*this, {}, {}, {}, {}, 0, {}};
  uint32_t leaf = static_cast<uint32_t>(
      std::upper_bound(leaf_start_.begin(), leaf_start_.end(), begin) - leaf_start_.begin() - 1);
  const bool use_avx2 = cpu_has_avx2();
  float guess = -1.0f;           // the previous leaf's largest k-th squared distance; < 0: none yet
  double previous_reach = -1.0;  // k-th distance of the previous row, < 0 when unknown
  auto write_row = [&](std::size_t p, std::size_t found) {
    previous_reach =
        found == others && others > 0 ? std::sqrt(double{key_d2(keys[others - 1])}) : -1.0;
    uint32_t* row_ids = indices + (p - begin) * k;
    float* row_d2 = sq_dists + (p - begin) * k;
    row_ids[0] = ids_[p];
    row_d2[0] = 0.0f;
    for (std::size_t c = 0; c < found; ++c) {
      row_ids[1 + c] = key_id(keys[c]);
      row_d2[1 + c] = key_d2(keys[c]);
    }
    for (std::size_t c = 1 + found; c < k; ++c) {
      row_ids[c] = kNone;
      row_d2[c] = kInf;
    }
  };
  // Warm start: if the previous point p' has its k - 1 others within distance D, then those and
  // p' itself (k points, at most one of them the current point) lie within D + |q - q'| of q, so
  // the current row needs nothing farther. The bound is computed in double and widened far beyond
  // float rounding, so it never cuts a true neighbour.
  auto search = [&](std::size_t p, uint32_t l) {
    uint64_t cap = ~uint64_t{0};
    if (p > begin && previous_reach >= 0.0) {
      const double dx = double{xs_[p]} - xs_[p - 1], dy = double{ys_[p]} - ys_[p - 1],
                   dz = double{zs_[p]} - zs_[p - 1];
      const double reach = previous_reach + std::sqrt(dx * dx + dy * dy + dz * dz);
      const double bound = reach * reach * (1.0 + 1e-5) + 1e-30;
      if (bound < std::numeric_limits<float>::max())
        cap = make_key(std::nextafter(static_cast<float>(bound), kInf), kNone);
    }
    KnnState state(others, keys.data(), cap);
    if (others > 0) {
      KnnSearch{*this, xs_[p], ys_[p], zs_[p], static_cast<uint32_t>(p), state}.from_leaf(l);
      state.finish();
    }
    write_row(p, state.count);
    return state.count == others && others > 0 ? key_d2(keys[others - 1]) : -1.0f;
  };
  for (std::size_t p = begin; p < end; leaf++) {
    while (leaf_start_[leaf + 1] <= p) ++leaf;  // empty leaves (max_leaf_size 1, n not 2^D)
    const std::size_t leaf_end = std::min<std::size_t>(end, leaf_start_[leaf + 1]);
    float farthest = -1.0f;
    if (guess < 0.0f || others == 0) guess = search(p++, leaf) * kGuessGrowth;
    const float reach2 = guess;
    if (p < leaf_end && guess >= 0.0f && std::isfinite(reach2) &&
        batch.gather(leaf, reach2, kCandidateLimit, use_avx2)) {
      for (; p < leaf_end; ++p) {
        const uint32_t q = static_cast<uint32_t>(p);
#if defined(__x86_64__)
        const bool answered = use_avx2 ? batch.rank_avx2(q, reach2, others, keys.data())
                                       : batch.query(q, reach2, others, keys.data());
#else
        const bool answered = batch.query(q, reach2, others, keys.data());
#endif
        if (!answered) {
          farthest = std::max(farthest, search(p, leaf));
          continue;
        }
        write_row(p, others);
        farthest = std::max(farthest, key_d2(keys[others - 1]));
      }
    }
    for (; p < leaf_end; ++p) farthest = std::max(farthest, search(p, leaf));
    guess = farthest * kGuessGrowth;
  }
}

void SpatialIndex::for_each_knn_block(std::size_t k, const KnnBlockFn& fn) const {
  if (k == 0 || size() == 0) return;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, size(), kBlockSize),
      [&](const tbb::blocked_range<std::size_t>& range) {
        std::vector<uint32_t> indices(range.size() * k);
        std::vector<float> sq_dists(range.size() * k);
        knn_rows(range.begin(), range.end(), k, indices.data(), sq_dists.data());
        fn(std::span<const uint32_t>(ids_.data() + range.begin(), range.size()), indices, sq_dists);
      },
      tbb::simple_partitioner());
}

void SpatialIndex::knn_all(std::size_t k, std::span<uint32_t> out_indices,
                           std::span<float> out_sq_dists) const {
  if (out_indices.size() != size() * k ||
      (!out_sq_dists.empty() && out_sq_dists.size() != size() * k)) {
    throw std::invalid_argument("SpatialIndex::knn_all: output spans must hold size() * k entries");
  }
  for_each_knn_block(k, [&](std::span<const uint32_t> queries, std::span<const uint32_t> indices,
                            std::span<const float> sq_dists) {
    for (std::size_t r = 0; r < queries.size(); ++r) {
      std::size_t row = std::size_t{queries[r]} * k;
      std::copy_n(indices.data() + r * k, k, out_indices.data() + row);
      if (!out_sq_dists.empty()) std::copy_n(sq_dists.data() + r * k, k, out_sq_dists.data() + row);
    }
  });
}

void SpatialIndex::radius(const Vec3f& q, float r, std::vector<uint32_t>& out_indices,
                          std::vector<float>* out_sq_dists) const {
  if (!(r >= 0.0f) || !std::isfinite(r)) {
    throw std::invalid_argument("SpatialIndex::radius: radius must be finite and >= 0");
  }
  out_indices.clear();
  if (out_sq_dists != nullptr) out_sq_dists->clear();
  if (size() == 0 || !is_finite(q)) return;
  const float r2 = r * r;
  struct Hit {
    float d2;
    uint32_t id;
  };
  std::vector<Hit> hits;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    uint32_t node = stack.back();
    stack.pop_back();
    if (box_sq_dist(boxes_[node], q.x, q.y, q.z) > r2) continue;
    if (node < first_leaf_) {
      stack.push_back(2 * node + 2);
      stack.push_back(2 * node + 1);
      continue;
    }
    uint32_t leaf = node - first_leaf_;
    for (uint32_t p = leaf_start_[leaf]; p < leaf_start_[leaf + 1]; ++p) {
      float dx = xs_[p] - q.x, dy = ys_[p] - q.y, dz = zs_[p] - q.z;
      float d = dx * dx + dy * dy + dz * dz;
      if (d <= r2) hits.push_back({d, ids_[p]});
    }
  }
  std::sort(hits.begin(), hits.end(),
            [](const Hit& a, const Hit& b) { return before(a.d2, a.id, b.d2, b.id); });
  out_indices.reserve(hits.size());
  for (const Hit& h : hits) out_indices.push_back(h.id);
  if (out_sq_dists != nullptr) {
    out_sq_dists->reserve(hits.size());
    for (const Hit& h : hits) out_sq_dists->push_back(h.d2);
  }
}

// The overlap rows of one leaf's points share one candidate set: the points p whose box distance
// to the leaf's box is below (r_leaf + r_p)^2, r_leaf the leaf's largest radius. For a query q of
// the leaf (r_q <= r_leaf) every point left out has d^2 >= (r_q + r_p)^2 (box distance and
// rounding are monotonic, as for the kNN pruning), so the rows are exact. A leaf whose set would
// be too large (huge radii nearby) uses the per-query search instead.
struct SpatialIndex::OverlapBatch {
  const SpatialIndex& index;
  const float* tree_radii;
  const float* node_max_radius;
  std::vector<float> cx, cy, cz, cr;  // candidates' coordinates and radii, padded to 8
  std::vector<uint32_t> cid;          // their original indices
  std::size_t size = 0;               // candidates plus padding
  std::vector<uint32_t> hits;         // one row's neighbours before sorting

  bool gather(uint32_t leaf, std::size_t limit) {
    const Box& b = index.boxes_[index.first_leaf_ + leaf];
    const float r_leaf = node_max_radius[index.first_leaf_ + leaf];
    const std::size_t room = limit + index.leaf_start_[1] + 1 + 8;
    if (cx.size() < room) {
      cx.resize(room), cy.resize(room), cz.resize(room), cr.resize(room), cid.resize(room);
      hits.resize(room + 8);
    }
    std::size_t count = 0;
    const bool within = index.visit_leaves(
        0,
        [&](uint32_t node) {
          const float reach = r_leaf + node_max_radius[node];
          return box_gap_sq(index.boxes_[node], b) >= reach * reach;
        },
        [&](uint32_t l) {
          if (count > limit) return false;
          for (uint32_t p = index.leaf_start_[l]; p < index.leaf_start_[l + 1]; ++p) {
            const float x = index.xs_[p], y = index.ys_[p], z = index.zs_[p], r = tree_radii[p];
            cx[count] = x, cy[count] = y, cz[count] = z, cr[count] = r;
            cid[count] = index.ids_[p];
            const float sum = r_leaf + r;
            count += box_sq_dist(b, x, y, z) < sum * sum;
          }
          return true;
        });
    if (!within || count > limit) return false;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t j = count; j % 8 != 0; ++j) cx[j] = cy[j] = cz[j] = cr[j] = nan;
    size = (count + 7) & ~std::size_t{7};
    return true;
  }

#if defined(__x86_64__)
  // row's test eight candidates at a time, the same float operations; the hits are packed.
  __attribute__((target("avx2"))) std::size_t row_avx2(uint32_t p) {
    const __m256 qx = _mm256_set1_ps(index.xs_[p]), qy = _mm256_set1_ps(index.ys_[p]),
                 qz = _mm256_set1_ps(index.zs_[p]), qr = _mm256_set1_ps(tree_radii[p]);
    const __m256i self = _mm256_set1_epi32(static_cast<int>(index.ids_[p]));
    std::size_t m = 0;
    for (std::size_t j = 0; j < size; j += 8) {
      const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(cx.data() + j), qx);
      const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(cy.data() + j), qy);
      const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(cz.data() + j), qz);
      const __m256 sum = _mm256_add_ps(qr, _mm256_loadu_ps(cr.data() + j));
      const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                      _mm256_mul_ps(dz, dz));
      const __m256i ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(cid.data() + j));
      const unsigned mask =
          static_cast<unsigned>(
              _mm256_movemask_ps(_mm256_cmp_ps(d2, _mm256_mul_ps(sum, sum), _CMP_LT_OQ))) &
          ~static_cast<unsigned>(
              _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(ids, self))));
      const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(kLaneCompress[mask]));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits.data() + m),
                          _mm256_permutevar8x32_epi32(ids, perm));
      m += static_cast<std::size_t>(std::popcount(mask));
    }
    return m;
  }

  // Appends hits[0, m) in ascending order (rank_sort_avx2).
  __attribute__((target("avx2"))) void sorted_avx2(std::size_t m,
                                                   std::vector<uint32_t>& neighbors) const {
    const std::size_t base = neighbors.size();
    neighbors.resize(base + m + 8);  // eight spare slots take the padding lanes
    rank_sort_avx2(hits.data(), m, neighbors.data() + base);
    neighbors.resize(base + m);
  }
#endif

  // The neighbours of the point at tree position p among the candidates, appended (sorted when
  // the AVX2 path sorts them; the caller sorts every row anyway).
  void row(uint32_t p, bool avx2, std::vector<uint32_t>& neighbors) {
#if defined(__x86_64__)
    if (avx2) {
      const std::size_t m = row_avx2(p);
      if (m <= kRankLimit) return sorted_avx2(m, neighbors);
      neighbors.insert(neighbors.end(), hits.begin(), hits.begin() + m);
      return;
    }
#endif
    const float qx = index.xs_[p], qy = index.ys_[p], qz = index.zs_[p], r = tree_radii[p];
    const uint32_t self = index.ids_[p];
    for (std::size_t j = 0; j < size; ++j) {
      const float dx = cx[j] - qx, dy = cy[j] - qy, dz = cz[j] - qz;
      const float sum = r + cr[j];
      if (dx * dx + dy * dy + dz * dz < sum * sum && cid[j] != self) neighbors.push_back(cid[j]);
    }
  }
};

// Rows of the overlap graph for tree positions [begin, end): original indices, each row sorted.
// Leaf by leaf from a shared candidate set (OverlapBatch); otherwise a query starts in its own
// leaf and climbs, like the batch kNN, visiting each sibling subtree unless even its largest
// radius cannot reach: box distance^2 >= (r_i + r_max)^2 implies d^2 >= (r_i + r_j)^2 for every
// point inside (rounding is monotonic), so pruning is exact. The climb stops once the node's
// faces are out of reach of the largest radius of all.
void SpatialIndex::overlap_rows(std::size_t begin, std::size_t end, const float* tree_radii,
                                const float* node_max_radius, std::vector<uint32_t>& neighbors,
                                std::vector<uint32_t>& counts) const {
  const bool use_avx2 = cpu_has_avx2();
  auto search = [&](std::size_t p, uint32_t leaf) {
    const float qx = xs_[p], qy = ys_[p], qz = zs_[p], r = tree_radii[p];
    auto scan_leaf = [&](uint32_t l) {
      for (uint32_t o = leaf_start_[l]; o < leaf_start_[l + 1]; ++o) {
        float dx = xs_[o] - qx, dy = ys_[o] - qy, dz = zs_[o] - qz;
        float sum = r + tree_radii[o];
        if (dx * dx + dy * dy + dz * dz < sum * sum && o != p) neighbors.push_back(ids_[o]);
      }
    };
    auto descend = [&](uint32_t root) {
      visit_leaves(
          root,
          [&](uint32_t node) {
            const float reach = r + node_max_radius[node];
            return box_sq_dist(boxes_[node], qx, qy, qz) >= reach * reach;
          },
          [&](uint32_t l) {
            scan_leaf(l);
            return true;
          });
    };
    scan_leaf(leaf);
    const float reach_all = r + node_max_radius[0];
    for (uint32_t node = first_leaf_ + leaf; node > 0; node = (node - 1) / 2) {
      if (inner_margin_sq(boxes_[node], qx, qy, qz) >= reach_all * reach_all) break;
      descend((node & 1) ? node + 1 : node - 1);
    }
  };
  OverlapBatch batch{*this, tree_radii, node_max_radius, {}, {}, {}, {}, {}, 0, {}};
  uint32_t leaf = static_cast<uint32_t>(
      std::upper_bound(leaf_start_.begin(), leaf_start_.end(), begin) - leaf_start_.begin() - 1);
  for (std::size_t p = begin; p < end; ++leaf) {
    const std::size_t leaf_end = std::min<std::size_t>(end, leaf_start_[leaf + 1]);
    const bool batched = batch.gather(leaf, kCandidateLimit);
    for (; p < leaf_end; ++p) {
      const std::size_t row_begin = neighbors.size();
      if (batched) {
        batch.row(static_cast<uint32_t>(p), use_avx2, neighbors);
      } else {
        search(p, leaf);
      }
      if (!std::is_sorted(neighbors.begin() + row_begin, neighbors.end()))
        std::sort(neighbors.begin() + row_begin, neighbors.end());
      counts.push_back(static_cast<uint32_t>(neighbors.size() - row_begin));
    }
  }
}

NeighborGraph SpatialIndex::sphere_overlaps(std::span<const float> radii) const {
  const std::size_t n = size();
  if (radii.size() != n) {
    throw std::invalid_argument("SpatialIndex::sphere_overlaps: need one radius per point");
  }
  for (float r : radii) {
    if (!(r >= 0.0f) || !std::isfinite(r)) {
      throw std::invalid_argument("SpatialIndex::sphere_overlaps: radii must be finite and >= 0");
    }
  }
  NeighborGraph graph;
  graph.offsets.assign(n + 1, 0);
  if (n == 0) return graph;

  std::vector<float> tree_radii(n);
  for (std::size_t p = 0; p < n; ++p) tree_radii[p] = radii[ids_[p]];
  std::vector<float> node_max_radius(boxes_.size());
  for (uint32_t leaf = 0; leaf + first_leaf_ < boxes_.size(); ++leaf) {
    float m = 0.0f;
    for (uint32_t p = leaf_start_[leaf]; p < leaf_start_[leaf + 1]; ++p) {
      m = std::max(m, tree_radii[p]);
    }
    node_max_radius[first_leaf_ + leaf] = m;
  }
  for (uint32_t node = first_leaf_; node-- > 0;) {
    node_max_radius[node] = std::max(node_max_radius[2 * node + 1], node_max_radius[2 * node + 2]);
  }

  const std::size_t blocks = (n + kBlockSize - 1) / kBlockSize;
  std::vector<std::vector<uint32_t>> block_neighbors(blocks), block_counts(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    overlap_rows(b * kBlockSize, std::min(n, (b + 1) * kBlockSize), tree_radii.data(),
                 node_max_radius.data(), block_neighbors[b], block_counts[b]);
  });

  for (std::size_t p = 0; p < n; ++p) {
    graph.offsets[std::size_t{ids_[p]} + 1] = block_counts[p / kBlockSize][p % kBlockSize];
  }
  for (std::size_t i = 0; i < n; ++i) graph.offsets[i + 1] += graph.offsets[i];
  graph.neighbors.resize(graph.offsets[n]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const uint32_t* src = block_neighbors[b].data();
    for (std::size_t p = b * kBlockSize; p < std::min(n, (b + 1) * kBlockSize); ++p) {
      uint32_t count = block_counts[b][p - b * kBlockSize];
      std::copy_n(src, count, graph.neighbors.data() + graph.offsets[ids_[p]]);
      src += count;
    }
    std::vector<uint32_t>().swap(block_neighbors[b]);
  });
  return graph;
}

}  // namespace splatkit
