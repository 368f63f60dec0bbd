#include "splatkit/spatial_index.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "splatkit/error.h"

namespace splatkit {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Batch queries are handed out in blocks of at most this many points (bounded scratch memory).
constexpr std::size_t kBlockSize = 1024;
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

inline bool before(float d_a, uint32_t id_a, float d_b, uint32_t id_b) {
  return d_a < d_b || (d_a == d_b && id_a < id_b);
}

}  // namespace

// The k best candidates so far, sorted by (squared distance, index): a fixed-size insertion array,
// which beats a heap for the small k of normal estimation.
struct SpatialIndex::KnnState {
  std::size_t k = 0;
  std::size_t count = 0;
  uint32_t* ids = nullptr;
  float* d2 = nullptr;

  float bound() const { return count < k ? kInf : d2[k - 1]; }
  void offer(float d, uint32_t id) {
    std::size_t pos;
    if (count < k) {
      pos = count++;
    } else {
      if (!before(d, id, d2[k - 1], ids[k - 1])) return;
      pos = k - 1;
    }
    while (pos > 0 && before(d, id, d2[pos - 1], ids[pos - 1])) {
      d2[pos] = d2[pos - 1];
      ids[pos] = ids[pos - 1];
      --pos;
    }
    d2[pos] = d;
    ids[pos] = id;
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
    std::nth_element(
        pts.begin() + begin, pts.begin() + mid, pts.begin() + end,
        [axis](const BuildPoint& a, const BuildPoint& b) { return a.c[axis] < b.c[axis]; });
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
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error(ErrorKind::kBadInput,
                  "spatial index: point " + std::to_string(i) + " has a non-finite coordinate");
    }
    pts[i] = {{p.x, p.y, p.z}, static_cast<uint32_t>(i)};
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

  xs_.resize(n);
  ys_.resize(n);
  zs_.resize(n);
  ids_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    xs_[i] = pts[i].c[0];
    ys_[i] = pts[i].c[1];
    zs_[i] = pts[i].c[2];
    ids_[i] = pts[i].id;
  }
}

std::size_t SpatialIndex::memory_bytes() const {
  return (xs_.capacity() + ys_.capacity() + zs_.capacity()) * sizeof(float) +
         ids_.capacity() * sizeof(uint32_t) + boxes_.capacity() * sizeof(Box) +
         leaf_start_.capacity() * sizeof(uint32_t);
}

// Depth-first, nearer child first, pruning every box farther than the current k-th candidate.
// A box exactly as far as the k-th candidate is still visited: it may hold a tie with a smaller
// index. The point at tree position skip_position (the query itself in batches) is ignored.
void SpatialIndex::search_knn(float qx, float qy, float qz, uint32_t skip_position,
                              KnnState& state) const {
  struct Pending {
    uint32_t node;
    float d2;
  };
  Pending stack[64];
  int top = 0;
  float d2_buffer[256];
  const float* xs = xs_.data();
  const float* ys = ys_.data();
  const float* zs = zs_.data();

  uint32_t node = 0;
  float node_d2 = box_sq_dist(boxes_[0], qx, qy, qz);
  for (;;) {
    if (node_d2 <= state.bound()) {
      while (node < first_leaf_) {
        uint32_t near = 2 * node + 1, far = near + 1;
        float near_d2 = box_sq_dist(boxes_[near], qx, qy, qz);
        float far_d2 = box_sq_dist(boxes_[far], qx, qy, qz);
        if (far_d2 < near_d2) {
          std::swap(near, far);
          std::swap(near_d2, far_d2);
        }
        float bound = state.bound();
        if (far_d2 <= bound) stack[top++] = {far, far_d2};
        if (near_d2 > bound) break;
        node = near;
      }
      if (node >= first_leaf_) {
        uint32_t leaf = node - first_leaf_;
        uint32_t begin = leaf_start_[leaf], end = leaf_start_[leaf + 1];
        // Distances first, in a loop the compiler vectorises; candidates second.
        for (uint32_t start = begin; start < end; start += 256) {
          uint32_t stop = std::min(end, start + 256);
          for (uint32_t p = start; p < stop; ++p) {
            float dx = xs[p] - qx, dy = ys[p] - qy, dz = zs[p] - qz;
            d2_buffer[p - start] = dx * dx + dy * dy + dz * dz;
          }
          for (uint32_t p = start; p < stop; ++p) {
            float d = d2_buffer[p - start];
            if (d <= state.bound() && p != skip_position) state.offer(d, ids_[p]);
          }
        }
      }
    }
    if (top == 0) break;
    --top;
    node = stack[top].node;
    node_d2 = stack[top].d2;
  }
}

std::size_t SpatialIndex::knn(const Vec3f& q, std::size_t k, uint32_t* out_indices,
                              float* out_sq_dists) const {
  k = std::min(k, size());
  if (k == 0) return 0;
  std::vector<float> scratch;
  if (out_sq_dists == nullptr) {
    scratch.resize(k);
    out_sq_dists = scratch.data();
  }
  KnnState state{k, 0, out_indices, out_sq_dists};
  search_knn(q.x, q.y, q.z, kNone, state);
  return state.count;
}

// Rows for the points at tree positions [begin, end), written consecutively (row r for position
// begin + r), each laid out as documented for knn_all.
void SpatialIndex::knn_rows(std::size_t begin, std::size_t end, std::size_t k, uint32_t* indices,
                            float* sq_dists) const {
  const std::size_t others = std::min(k - 1, size() - 1);
  for (std::size_t p = begin; p < end; ++p) {
    uint32_t* row_ids = indices + (p - begin) * k;
    float* row_d2 = sq_dists + (p - begin) * k;
    row_ids[0] = ids_[p];
    row_d2[0] = 0.0f;
    KnnState state{others, 0, row_ids + 1, row_d2 + 1};
    if (others > 0) search_knn(xs_[p], ys_[p], zs_[p], static_cast<uint32_t>(p), state);
    for (std::size_t c = 1 + state.count; c < k; ++c) {
      row_ids[c] = kNone;
      row_d2[c] = kInf;
    }
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
  if (size() == 0) return;
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

// Rows of the overlap graph for tree positions [begin, end): original indices, each row sorted.
// A node is skipped when even its largest radius cannot reach: box distance^2 >= (r_i + r_max)^2
// implies d^2 >= (r_i + r_j)^2 for every point inside (rounding is monotonic), so it is exact.
void SpatialIndex::overlap_rows(std::size_t begin, std::size_t end, const float* tree_radii,
                                const float* node_max_radius, std::vector<uint32_t>& neighbors,
                                std::vector<uint32_t>& counts) const {
  std::vector<uint32_t> stack;
  for (std::size_t p = begin; p < end; ++p) {
    const float qx = xs_[p], qy = ys_[p], qz = zs_[p], r = tree_radii[p];
    const std::size_t row_begin = neighbors.size();
    stack.assign(1, 0);
    while (!stack.empty()) {
      uint32_t node = stack.back();
      stack.pop_back();
      float reach = r + node_max_radius[node];
      if (box_sq_dist(boxes_[node], qx, qy, qz) >= reach * reach) continue;
      if (node < first_leaf_) {
        stack.push_back(2 * node + 2);
        stack.push_back(2 * node + 1);
        continue;
      }
      uint32_t leaf = node - first_leaf_;
      for (uint32_t o = leaf_start_[leaf]; o < leaf_start_[leaf + 1]; ++o) {
        float dx = xs_[o] - qx, dy = ys_[o] - qy, dz = zs_[o] - qz;
        float sum = r + tree_radii[o];
        if (dx * dx + dy * dy + dz * dz < sum * sum && o != p) neighbors.push_back(ids_[o]);
      }
    }
    std::sort(neighbors.begin() + row_begin, neighbors.end());
    counts.push_back(static_cast<uint32_t>(neighbors.size() - row_begin));
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
