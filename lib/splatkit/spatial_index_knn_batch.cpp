#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <bit>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "splatkit/lane_compress.h"
#include "splatkit/simd_level.h"
#include "splatkit/spatial_index.h"
#include "splatkit/spatial_index_search.h"

namespace splatkit {

using namespace spatial_index_detail;

namespace {

// A leaf's shared candidate set reaches this factor times the previous leaf's largest k-th
// squared distance.
constexpr float kGuessGrowth = 1.1f;
// rank_avx2 counts ranks for up to this many candidates within the cap (quadratic), and sorts
// beyond.
constexpr std::size_t kRankLimit = 160;

}  // namespace

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

  // The portable path of rank_avx2, the same answer: a cap-filtered insertion (four candidates
  // at a time with sse2).
  bool query(uint32_t p, float cap, std::size_t others, uint64_t* keys, bool sse2) const {
#if defined(__SSE2__)
    if (sse2) return query_sse2(p, cap, others, keys);
#endif
    KnnState state(others, keys, make_key(cap, kNone));
    const uint32_t self = index.ids_[p];
    const float qx = index.xs_[p], qy = index.ys_[p], qz = index.zs_[p];
    for (std::size_t j = 0; j < size; ++j) {
      const float dx = cx[j] - qx, dy = cy[j] - qy, dz = cz[j] - qz;
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (!(d2 <= key_d2_or_inf(state.worst))) continue;
      const uint64_t key = make_key(d2, cid[j]);
      if (key < state.worst && cid[j] != self) state.insert(key);
    }
    return state.count == others;
  }

#if defined(__SSE2__)
  // query four candidates at a time.
  bool query_sse2(uint32_t p, float cap, std::size_t others, uint64_t* keys) const {
    KnnState state(others, keys, make_key(cap, kNone));
    const uint32_t self = index.ids_[p];
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
    return state.count == others;
  }
#endif
};

// Rows for the points at tree positions [begin, end), written consecutively (row r for position
// begin + r), each laid out as documented for knn_all. Leaf by leaf: a shared candidate set
// (LeafBatch) answers most queries; the rest, and the first query of a range (which sets the
// guess), use the ordinary search from their own leaf.
void SpatialIndex::knn_rows(std::size_t begin, std::size_t end, std::size_t k, uint32_t* indices,
                            float* sq_dists) const {
  const std::size_t others = std::min(k - 1, size() - 1);
  std::vector<uint64_t> keys(others + 1);
  LeafBatch batch{*this, {}, {}, {}, {}, 0, {}};
  uint32_t leaf = static_cast<uint32_t>(
      std::upper_bound(leaf_start_.begin(), leaf_start_.end(), begin) - leaf_start_.begin() - 1);
  const SimdLevel level = simd_level();
  const bool use_avx2 = level >= SimdLevel::kAvx2, use_sse2 = level >= SimdLevel::kSse2;
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
      KnnSearch{*this, xs_[p], ys_[p], zs_[p], static_cast<uint32_t>(p), state, use_sse2}.from_leaf(
          l);
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
                                       : batch.query(q, reach2, others, keys.data(), use_sse2);
#else
        const bool answered = batch.query(q, reach2, others, keys.data(), use_sse2);
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
  simd_level();  // a bad SPLATKIT_SIMD is reported here, before any work
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

}  // namespace splatkit
