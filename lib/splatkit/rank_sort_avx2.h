// Sorting a short list of distinct uint32 indices without data-dependent branches (AVX2): each
// value's rank is the count of smaller ones, compared as signed after flipping the top bit, and
// the value is stored at its rank. Quadratic: for rows up to a few hundred entries (kd-tree and
// grid neighbour rows), where it beats std::sort's mispredicted branches. Shared by SpatialIndex
// and graph::sphere_overlap_graph; callers check simd_level() >= SimdLevel::kAvx2 first
// (splatkit/simd_level.h).
#pragma once

#if defined(__x86_64__)
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

namespace splatkit {

// in[0, m): distinct values, readable up to the next multiple of 8 (padding lanes are ignored);
// out: m + 8 writable slots (the padding lanes land in out[m, m + 8)). Writes in's values to
// out[0, m) in ascending order.
__attribute__((target("avx2"))) inline void rank_sort_avx2(const uint32_t* in, std::size_t m,
                                                           uint32_t* out) {
  const __m256i flip = _mm256_set1_epi32(static_cast<int>(0x80000000u));
  for (std::size_t i0 = 0; i0 < m; i0 += 8) {
    const __m256i vi =
        _mm256_xor_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in + i0)), flip);
    __m256i rank = _mm256_setzero_si256();
    for (std::size_t j = 0; j < m; ++j)
      rank = _mm256_sub_epi32(
          rank, _mm256_cmpgt_epi32(vi, _mm256_set1_epi32(static_cast<int>(in[j] ^ 0x80000000u))));
    alignas(32) uint32_t ranks[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(ranks), rank);
    for (std::size_t lane = 0; lane < 8; ++lane)
      out[i0 + lane < m ? ranks[lane] : m + lane] = in[i0 + lane];
  }
}

}  // namespace splatkit
#endif
