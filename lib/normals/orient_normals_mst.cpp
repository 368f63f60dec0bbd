#include "normals/orient_normals_mst.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "splatkit/for_each_chunk.h"

namespace splatkit {

namespace {

constexpr uint32_t kNone = SpatialIndex::kNone;
constexpr float kParallel = 0.70710678f;  // cos 45°

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

// The kNN graph with every edge once: row i holds, in rank order, the neighbours j of i whose
// reverse edge j -> i is not in the earlier row j (the agreement is symmetric, so Kruskal would
// meet that one first and always reject this one; in a kNN graph most edges come in such pairs).
// Rows are compacted: row i is neighbors[start[i] .. start[i + 1]). An edge is named by
// (i << shift) | s, s its place in row i. Weights are not stored: the sort computes them as it
// goes (twice), which keeps 2 bytes per edge off the peak.
template <typename Id>
struct KnnGraph {
  unsigned shift = 0;
  std::vector<Id> start;
  ShrinkableArray neighbors{0};
  std::size_t size() const { return start.size() - 1; }
  uint32_t row_size(std::size_t i) const { return static_cast<uint32_t>(start[i + 1] - start[i]); }
};

constexpr std::size_t kRows = 1 << 15;  // rows per task of the passes below

// The rows of the k nearest neighbours (k - 1 besides the point itself), compacted in place.
template <typename Id>
KnnGraph<Id> build_graph(ShrinkableArray nb, std::size_t n, std::size_t k) {
  const std::size_t w = k - 1;
  // Which slots stay, decided on the full rows (read-only, in parallel).
  std::vector<uint8_t> keep(n * w);
  const std::size_t chunks = chunk_count(n, kRows);
  for_each_chunk(n, kRows, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t s = 0; s < w; ++s) {
        const uint32_t j = nb[i * w + s];
        const uint32_t* row = nb.data() + std::size_t{j} * w;
        keep[i * w + s] = j > i || std::find(row, row + w, uint32_t(i)) == row + w;
      }
  });
  // Each chunk compacts its rows within its own range (in parallel), then the chunks move down
  // in order (each lands at or below where it was, past the chunks before it).
  KnnGraph<Id> g;
  g.shift = static_cast<unsigned>(std::bit_width(w));
  g.start.resize(n + 1);
  std::vector<std::size_t> kept(chunks + 1, 0);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::size_t at = begin * w;
    for (std::size_t i = begin; i < end; ++i) {
      g.start[i] = static_cast<Id>(at - begin * w);
      for (std::size_t s = 0; s < w; ++s)
        if (keep[i * w + s]) nb[at++] = nb[i * w + s];
    }
    kept[c + 1] = at - begin * w;
  });
  keep = {};
  for (std::size_t c = 0; c < chunks; ++c) {
    std::copy_n(nb.data() + c * kRows * w, kept[c + 1], nb.data() + kept[c]);
    kept[c + 1] += kept[c];
  }
  g.start[n] = static_cast<Id>(kept[chunks]);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) g.start[i] += static_cast<Id>(kept[c]);
  });
  nb.shrink(kept[chunks]);
  g.neighbors = std::move(nb);
  return g;
}

// Edges sorted by key, ties by (row, place in the row) (a stable counting sort, in parallel over
// fixed chunks of rows: each chunk counts its keys and writes after the earlier chunks' share of
// every bucket, so the order is the serial one for any thread count).
template <typename Id>
std::vector<Id> sort_edges(const KnnGraph<Id>& g, std::span<const Vec3f> positions,
                           std::span<const Vec3f> normals) {
  const std::size_t n = g.size();
  auto key = [&](std::size_t i, uint32_t j) {
    return weight_key(agreement(positions[i], normals[i], positions[j], normals[j]));
  };
  // fn(i, s, j) for the edges of chunk c's rows.
  auto for_each_edge = [&](std::size_t c, auto&& fn) {
    for (std::size_t i = c * kRows; i < std::min(n, (c + 1) * kRows); ++i) {
      const uint32_t* row = g.neighbors.data() + g.start[i];
      for (uint32_t s = 0, m = g.row_size(i); s < m; ++s) fn(i, s, row[s]);
    }
  };
  const std::size_t chunks = (n + kRows - 1) / kRows;
  std::vector<uint64_t> start(chunks * kOrientBuckets, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    uint64_t* count = start.data() + c * kOrientBuckets;
    for_each_edge(c, [&](std::size_t i, uint32_t, uint32_t j) { ++count[key(i, j)]; });
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
    for_each_edge(c, [&](std::size_t i, uint32_t s, uint32_t j) {
      order[next[key(i, j)]++] = static_cast<Id>((static_cast<Id>(i) << g.shift) | s);
    });
  });
  return order;
}

// Union-find whose links carry a parity: flip(x) is whether x's sign is the opposite of its set
// root's. Joining two sets along a tree edge sets the parity of the new link so that the edge's
// relation holds; the relation between any two points of a set is then the product of the
// relations along their path in the spanning forest, which is what propagating signs over the
// forest breadth first gives, without storing the forest.
class SignedUnionFind {
 public:
  explicit SignedUnionFind(std::size_t n) : parent_(n), rank_(n, 0), flip_(n, 0) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<uint32_t>(i);
  }
  // The root of x's set; `flip` gets x's parity relative to it.
  uint32_t find(uint32_t x, uint8_t& flip) {
    uint8_t acc = 0;
    while (parent_[x] != x) {
      const uint32_t p = parent_[x];
      if (parent_[p] != p) {  // path halving: link x to its grandparent
        flip_[x] ^= flip_[p];
        parent_[x] = parent_[p];
      }
      acc ^= flip_[x];
      x = parent_[x];
    }
    flip = acc;
    return x;
  }
  // Joins the sets of a and b so that b's sign is a's (opposite(): a's negated); false when they
  // were already one set. opposite() is asked only when they were not: most edges Kruskal meets
  // join nothing, and their relation would cost the reads of both points' data.
  template <class Opposite>
  bool unite(uint32_t a, uint32_t b, Opposite&& opposite) {
    uint8_t fa, fb;
    a = find(a, fa), b = find(b, fb);
    if (a == b) return false;
    const bool flip = fa ^ fb ^ (opposite() ? 1 : 0);
    if (rank_[a] < rank_[b]) std::swap(a, b);
    parent_[b] = a;
    flip_[b] = static_cast<uint8_t>(flip);
    if (rank_[a] == rank_[b]) ++rank_[a];
    return true;
  }

 private:
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> rank_, flip_;
};

// Kruskal over the sorted edges with the signed union-find: the minimum spanning forest's
// relations (flip n_j when a < 0) are recorded as the sets join. Returns the sets.
template <typename Id>
SignedUnionFind spanning_forest(const KnnGraph<Id>& g, std::span<const Vec3f> positions,
                                std::span<const Vec3f> normals) {
  const std::size_t n = positions.size();
  SignedUnionFind sets(n);
  const std::vector<Id> order = sort_edges<Id>(g, positions, normals);
  const Id mask = (Id{1} << g.shift) - 1;
  std::size_t joined = 0;
  for (const Id e : order) {
    const auto i = static_cast<uint32_t>(e >> g.shift);
    const uint32_t j = g.neighbors[g.start[i] + (e & mask)];
    const auto opposite = [&] {
      return agreement(positions[i], normals[i], positions[j], normals[j]) < 0;
    };
    if (sets.unite(i, j, opposite) && ++joined + 1 == n) break;  // one set: the forest is whole
  }
  return sets;
}

// +1 / -1 per point from the sets: each set's top-most point (largest z, smallest index on ties)
// points +z, the rest follow their parity relative to it. Returns the number of sets.
std::size_t assign_signs(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                         SignedUnionFind& sets, std::vector<int8_t>& sign) {
  const std::size_t n = positions.size();
  std::vector<uint32_t> root(n);
  std::vector<uint8_t> flip(n);
  for (std::size_t i = 0; i < n; ++i) root[i] = sets.find(static_cast<uint32_t>(i), flip[i]);
  std::vector<uint32_t> seed(n, kNone);  // per root: its set's top-most point
  std::size_t components = 0;
  for (std::size_t i = 0; i < n; ++i) {
    uint32_t& s = seed[root[i]];
    components += s == kNone;
    if (s == kNone || positions[i].z > positions[s].z) s = static_cast<uint32_t>(i);
  }
  sign.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t s = seed[root[i]];
    const bool seed_up = !(normals[s].z < 0);
    sign[i] = static_cast<int8_t>((seed_up != (flip[i] != flip[s])) ? 1 : -1);
  }
  return components;
}

}  // namespace

void index_knn_rows(const SpatialIndex& index, std::size_t k, std::span<uint32_t> out) {
  const std::size_t w = k - 1;
  index.for_each_knn_block(k, [&](std::span<const uint32_t> queries,
                                  std::span<const uint32_t> indices, std::span<const float>) {
    for (std::size_t r = 0; r < queries.size(); ++r)  // column 0 is the point itself
      std::copy_n(indices.data() + r * k + 1, w, out.data() + queries[r] * w);
  });
}

ShrinkableArray orient_knn_rows(const KnnRowsFn& rows, std::size_t n, std::size_t k) {
  if (k < 2) throw std::invalid_argument("orient_normals_mst: k must be at least 2");
  k = std::min(k, n);
  ShrinkableArray out(n * (k > 0 ? k - 1 : 0));  // every slot is written by rows: k <= n
  if (k > 1) rows(k, std::span<uint32_t>(out.data(), out.size()));
  return out;
}

OrientStats orient_normals_mst(SpatialIndex index, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  if (index.size() != positions.size())
    throw std::invalid_argument("orient_normals_mst: positions and index differ in size");
  ShrinkableArray rows = orient_knn_rows(
      [&](std::size_t row_k, std::span<uint32_t> out) { index_knn_rows(index, row_k, out); },
      positions.size(), k);
  index = SpatialIndex();  // released before the graph's peak
  return orient_normals_mst(std::move(rows), positions, normals, k);
}

OrientStats orient_normals_mst(const KnnRowsFn& rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  return orient_normals_mst(orient_knn_rows(rows, positions.size(), k), positions, normals, k);
}

OrientStats orient_normals_mst(ShrinkableArray rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  if (k < 2) throw std::invalid_argument("orient_normals_mst: k must be at least 2");
  const std::size_t n = positions.size();
  if (normals.size() != n)
    throw std::invalid_argument("orient_normals_mst: positions and normals differ in size");
  if (rows.size() != n * (std::min(k, n) > 0 ? std::min(k, n) - 1 : 0))
    throw std::invalid_argument("orient_normals_mst: the kNN rows do not match the points");
  OrientStats stats;
  if (n == 0) return stats;

  // 32-bit edge names and row starts while (n << shift) fits, which also bounds the edges.
  auto forest = [&]<typename Id>(Id) {
    const KnnGraph<Id> graph = build_graph<Id>(std::move(rows), n, std::min(k, n));
    return spanning_forest<Id>(graph, positions, normals);
  };
  const std::size_t width = std::min(k, n) - 1;
  SignedUnionFind sets =
      (uint64_t{n} << std::bit_width(width)) <= std::numeric_limits<uint32_t>::max()
          ? forest(uint32_t{})
          : forest(uint64_t{});
  std::vector<int8_t> sign;
  stats.components = assign_signs(positions, normals, sets, sign);
  for (std::size_t i = 0; i < n; ++i) {
    if (sign[i] < 0) {
      normals[i] = -normals[i];
      ++stats.flipped;
    }
  }
  return stats;
}

}  // namespace splatkit
