#include <tbb/parallel_for.h>

#include <algorithm>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <bit>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "splatkit/error.h"
#include "splatkit/lane_compress.h"
#include "splatkit/rank_sort_avx2.h"
#include "splatkit/simd_level.h"
#include "splatkit/spatial_index.h"
#include "splatkit/spatial_index_search.h"

namespace splatkit {

using namespace spatial_index_detail;

namespace {

// OverlapBatch sorts rows of up to this many entries by ranking (quadratic), longer ones by
// std::sort.
constexpr std::size_t kRankLimit = 160;

}  // namespace

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
bool SpatialIndex::overlap_rows(std::size_t begin, std::size_t end, const float* tree_radii,
                                const float* node_max_radius, std::vector<uint32_t>& neighbors,
                                std::vector<uint32_t>& counts, std::atomic<std::size_t>& entries,
                                std::size_t max) const {
  const bool use_avx2 = simd_level() >= SimdLevel::kAvx2;
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
      const std::size_t row = neighbors.size() - row_begin;
      if (entries.fetch_add(row, std::memory_order_relaxed) + row > max) return false;
    }
  }
  return true;
}

void throw_too_many_overlaps(std::size_t max_entries, std::size_t spheres, float largest_radius) {
  std::ostringstream what;
  what << "the bounding spheres overlap more than " << max_entries << " times in all (over "
       << max_entries / std::max<std::size_t>(spheres, 1)
       << " neighbours per sphere; the largest radius is " << largest_radius
       << "): radii far larger than the spacing of the points";
  throw Error(ErrorKind::kBadInput, what.str());
}

NeighborGraph SpatialIndex::sphere_overlaps(std::span<const float> radii,
                                            std::size_t max_entries) const {
  const std::size_t n = size();
  if (radii.size() != n) {
    throw std::invalid_argument("SpatialIndex::sphere_overlaps: need one radius per point");
  }
  for (float r : radii) {
    if (!(r >= 0.0f) || !std::isfinite(r)) {
      throw std::invalid_argument("SpatialIndex::sphere_overlaps: radii must be finite and >= 0");
    }
  }
  simd_level();  // a bad SPLATKIT_SIMD is reported here, before any work
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
  std::atomic<std::size_t> entries{0};
  std::atomic<bool> full{false};
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    if (full.load(std::memory_order_relaxed)) return;
    if (!overlap_rows(b * kBlockSize, std::min(n, (b + 1) * kBlockSize), tree_radii.data(),
                      node_max_radius.data(), block_neighbors[b], block_counts[b], entries,
                      max_entries))
      full = true;
  });
  if (full) throw_too_many_overlaps(max_entries, n, node_max_radius[0]);

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