#include "normals/orient_normals_mst.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace splatkit {

namespace {

constexpr uint32_t kNone = SpatialIndex::kNone;
constexpr float kParallel = 0.70710678f;  // cos 45°

// The kNN graph as fixed-length rows (k - 1 neighbours per point, kNone where the cloud is
// smaller). Weights are not stored: the sort computes them as it goes (twice), which keeps 2 bytes
// per edge off the peak.
struct KnnGraph {
  std::size_t width = 0;  // neighbours per row
  std::vector<uint32_t> neighbors;
};

// The agreement of a pair's signs: positive when consistently oriented, its magnitude the
// confidence. Normals within 45° of parallel (or antiparallel): Hoppe's n_i·n_j, which the noise
// of the positions does not touch. Normals further apart (a crease, sharp with robust normals):
// n_i·n_j', where n_j' is n_j mirrored in the plane bisecting the edge x_i x_j (König & Gumhold
// 2009); n_i·n_j alone is ~0 across a 90° crease and negative across a 60° wedge's 120° jump
// for a consistent pair, while the mirror image still agrees with n_i.
float agreement(const Vec3f& xi, const Vec3f& ni, const Vec3f& xj, const Vec3f& nj) {
  const float d = dot(ni, nj);
  const Vec3f e = xj - xi;
  const float e2 = squared_norm(e);
  if (std::fabs(d) >= kParallel || !(e2 > 0)) return d;
  return d - 2 * dot(ni, e) * dot(nj, e) / e2;
}

uint16_t weight_key(float agree) {
  const float w = std::max(0.0f, 1.0f - std::fabs(agree));
  const float q = std::sqrt(w) * static_cast<float>(kOrientBuckets);
  return static_cast<uint16_t>(std::min(q, static_cast<float>(kOrientBuckets - 1)));
}

KnnGraph build_graph(const SpatialIndex& index, std::size_t k) {
  KnnGraph g;
  g.width = k - 1;
  const std::size_t n = index.size();
  g.neighbors.assign(n * g.width, kNone);
  index.for_each_knn_block(k, [&](std::span<const uint32_t> queries,
                                  std::span<const uint32_t> indices, std::span<const float>) {
    for (std::size_t r = 0; r < queries.size(); ++r) {
      // Column 0 is the point itself; the rest are its neighbours.
      std::copy_n(indices.data() + r * k + 1, g.width, g.neighbors.data() + queries[r] * g.width);
    }
  });
  return g;
}

// Edge ids sorted by key, ties by id (a stable counting sort, in parallel over fixed chunks of
// rows: each chunk counts its keys and writes after the earlier chunks' share of every bucket, so
// the order is the serial one for any thread count). Left out: slots without a neighbour, and an
// edge i -> j whose reverse j -> i is in the earlier row j (j < i): the two have the same key
// (the agreement is symmetric), so Kruskal meets the earlier one first and would always reject
// this one; in a kNN graph most edges come in such pairs.
template <typename Id>
std::vector<Id> sort_edges(const KnnGraph& g, std::span<const Vec3f> positions,
                           std::span<const Vec3f> normals) {
  const std::size_t w = g.width;
  if (w == 0) return {};  // a cloud of one point
  const std::size_t n = g.neighbors.size() / w;
  const uint32_t* nb = g.neighbors.data();
  auto kept = [&](std::size_t i, uint32_t j) {
    if (j == kNone) return false;
    if (j > i) return true;
    const uint32_t* row = nb + std::size_t{j} * w;
    return std::find(row, row + w, static_cast<uint32_t>(i)) == row + w;
  };
  auto key = [&](std::size_t i, uint32_t j) {
    return weight_key(agreement(positions[i], normals[i], positions[j], normals[j]));
  };
  constexpr std::size_t kRows = 1 << 15;
  const std::size_t chunks = (n + kRows - 1) / kRows;
  std::vector<uint64_t> start(chunks * kOrientBuckets, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    uint64_t* count = start.data() + c * kOrientBuckets;
    for (std::size_t i = c * kRows; i < std::min(n, (c + 1) * kRows); ++i)
      for (std::size_t s = 0; s < w; ++s) {
        const uint32_t j = nb[i * w + s];
        if (kept(i, j)) ++count[key(i, j)];
      }
  });
  uint64_t at = 0;
  for (std::size_t b = 0; b < kOrientBuckets; ++b)
    for (std::size_t c = 0; c < chunks; ++c) {
      const uint64_t count = start[c * kOrientBuckets + b];
      start[c * kOrientBuckets + b] = at;
      at += count;
    }
  std::vector<Id> order(at);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    uint64_t* next = start.data() + c * kOrientBuckets;
    for (std::size_t i = c * kRows; i < std::min(n, (c + 1) * kRows); ++i)
      for (std::size_t s = 0; s < w; ++s) {
        const uint32_t j = nb[i * w + s];
        if (kept(i, j)) order[next[key(i, j)]++] = static_cast<Id>(i * w + s);
      }
  });
  return order;
}

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n), rank_(n, 0) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<uint32_t>(i);
  }
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving
      x = parent_[x];
    }
    return x;
  }
  // Joins the sets of a and b; false when they were already one.
  bool unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    if (rank_[a] < rank_[b]) std::swap(a, b);
    parent_[b] = a;
    if (rank_[a] == rank_[b]) ++rank_[a];
    return true;
  }

 private:
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> rank_;
};

// Kruskal over the sorted edges: the minimum spanning forest as (i, j) pairs, plus each point's
// component root.
template <typename Id>
std::vector<std::pair<uint32_t, uint32_t>> spanning_forest(const KnnGraph& g,
                                                           std::span<const Vec3f> positions,
                                                           std::span<const Vec3f> normals,
                                                           std::vector<uint32_t>& root) {
  const std::size_t n = positions.size();
  std::vector<std::pair<uint32_t, uint32_t>> tree;
  UnionFind sets(n);
  {
    const std::vector<Id> order = sort_edges<Id>(g, positions, normals);
    tree.reserve(n > 0 ? n - 1 : 0);
    for (const Id e : order) {
      const auto i = static_cast<uint32_t>(e / g.width);
      const uint32_t j = g.neighbors[e];
      if (sets.unite(i, j)) {
        tree.emplace_back(i, j);
        if (tree.size() + 1 == n) break;  // one component: the tree is complete
      }
    }
  }
  root.resize(n);
  for (std::size_t i = 0; i < n; ++i) root[i] = sets.find(static_cast<uint32_t>(i));
  return tree;
}

// Compressed adjacency of the forest.
struct Adjacency {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> targets;
};

Adjacency forest_adjacency(const std::vector<std::pair<uint32_t, uint32_t>>& tree, std::size_t n) {
  Adjacency a;
  a.offsets.assign(n + 1, 0);
  for (const auto& [i, j] : tree) ++a.offsets[i + 1], ++a.offsets[j + 1];
  for (std::size_t i = 0; i < n; ++i) a.offsets[i + 1] += a.offsets[i];
  a.targets.resize(a.offsets[n]);
  std::vector<uint32_t> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (const auto& [i, j] : tree) a.targets[fill[i]++] = j, a.targets[fill[j]++] = i;
  return a;
}

// +1 / -1 per point: the sign that makes normals[i] consistent over its tree and outward at the
// component's top-most point. Returns the number of components.
std::size_t propagate_signs(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                            const Adjacency& adj, const std::vector<uint32_t>& root,
                            std::vector<int8_t>& sign) {
  const std::size_t n = positions.size();
  std::vector<uint32_t> seed(n, kNone);  // per root: its component's top-most point
  for (std::size_t i = 0; i < n; ++i) {
    uint32_t& s = seed[root[i]];
    if (s == kNone || positions[i].z > positions[s].z) s = static_cast<uint32_t>(i);
  }
  sign.assign(n, 0);
  std::size_t components = 0;
  std::vector<uint32_t> queue;
  for (std::size_t r = 0; r < n; ++r) {
    if (seed[r] == kNone) continue;
    ++components;
    const uint32_t s = seed[r];
    sign[s] = normals[s].z < 0 ? -1 : 1;
    queue.assign(1, s);
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const uint32_t i = queue[head];
      for (uint32_t e = adj.offsets[i]; e < adj.offsets[i + 1]; ++e) {
        const uint32_t j = adj.targets[e];
        if (sign[j] != 0) continue;
        const float agree = agreement(positions[i], normals[i], positions[j], normals[j]);
        sign[j] = static_cast<int8_t>(agree < 0 ? -sign[i] : sign[i]);
        queue.push_back(j);
      }
    }
  }
  return components;
}

}  // namespace

OrientStats orient_normals_mst(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  if (k < 2) throw std::invalid_argument("orient_normals_mst: k must be at least 2");
  const std::size_t n = positions.size();
  if (normals.size() != n || index.size() != n)
    throw std::invalid_argument("orient_normals_mst: positions, normals and index differ in size");
  OrientStats stats;
  if (n == 0) return stats;

  std::vector<uint32_t> root;
  std::vector<std::pair<uint32_t, uint32_t>> tree;
  {
    const KnnGraph graph = build_graph(index, std::min(k, n));
    tree = graph.neighbors.size() <= std::numeric_limits<uint32_t>::max()
               ? spanning_forest<uint32_t>(graph, positions, normals, root)
               : spanning_forest<uint64_t>(graph, positions, normals, root);
  }
  std::vector<int8_t> sign;
  {
    const Adjacency adj = forest_adjacency(tree, n);
    tree = {};
    stats.components = propagate_signs(positions, normals, adj, root, sign);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (sign[i] < 0) {
      normals[i] = -normals[i];
      ++stats.flipped;
    }
  }
  return stats;
}

}  // namespace splatkit
