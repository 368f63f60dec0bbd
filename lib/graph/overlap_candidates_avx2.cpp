// Candidates' AVX2 path: copy and test eight splats at a time, rows sorted by ranking.
#include "graph/overlap_candidates.h"

#if defined(__x86_64__)
#include <immintrin.h>

#include <bit>
#include <cstdint>
#include <span>

#include "splatkit/lane_compress.h"
#include "splatkit/rank_sort_avx2.h"

namespace splatkit::graph::overlap {

// gather's copy and test, eight splats at a time (the arrays are padded; lanes past a run's
// end are masked off).
__attribute__((target("avx2"))) uint32_t Candidates::copy_avx2(const Sorted& s, const Runs& runs,
                                                               const float lo[3], const float hi[3],
                                                               float r_cell) {
  const __m256 lx = _mm256_set1_ps(lo[0]), ly = _mm256_set1_ps(lo[1]), lz = _mm256_set1_ps(lo[2]);
  const __m256 hx = _mm256_set1_ps(hi[0]), hy = _mm256_set1_ps(hi[1]), hz = _mm256_set1_ps(hi[2]);
  const __m256 rc = _mm256_set1_ps(r_cell), big = _mm256_set1_ps(s.small_radius);
  const __m256 zero = _mm256_setzero_ps();
  uint32_t count = 0;
  for (const auto& [a, b] : runs)
    for (std::size_t q = a; q < b; q += 8) {
      const __m256 qx = _mm256_loadu_ps(s.x.data() + q), qy = _mm256_loadu_ps(s.y.data() + q),
                   qz = _mm256_loadu_ps(s.z.data() + q), qr = _mm256_loadu_ps(s.r.data() + q);
      const __m256i ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.id.data() + q));
      const __m256 gx =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lx, qx), _mm256_sub_ps(qx, hx)), zero);
      const __m256 gy =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(ly, qy), _mm256_sub_ps(qy, hy)), zero);
      const __m256 gz =
          _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lz, qz), _mm256_sub_ps(qz, hz)), zero);
      const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(gx, gx), _mm256_mul_ps(gy, gy)),
                                      _mm256_mul_ps(gz, gz));
      const __m256 sum = _mm256_add_ps(rc, qr);
      const __m256 keep = _mm256_and_ps(_mm256_cmp_ps(d2, _mm256_mul_ps(sum, sum), _CMP_LT_OQ),
                                        _mm256_cmp_ps(qr, big, _CMP_LE_OQ));
      const unsigned lanes = b - q >= 8 ? 0xFFu : (1u << (b - q)) - 1;
      const unsigned mask = unsigned(_mm256_movemask_ps(keep)) & lanes;
      const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(int64_t(kLaneCompress[mask])));
      _mm256_storeu_ps(x.data() + count, _mm256_permutevar8x32_ps(qx, perm));
      _mm256_storeu_ps(y.data() + count, _mm256_permutevar8x32_ps(qy, perm));
      _mm256_storeu_ps(z.data() + count, _mm256_permutevar8x32_ps(qz, perm));
      _mm256_storeu_ps(r.data() + count, _mm256_permutevar8x32_ps(qr, perm));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(id.data() + count),
                          _mm256_permutevar8x32_epi32(ids, perm));
      if (sharp) {
        _mm256_storeu_ps(nx.data() + count,
                         _mm256_permutevar8x32_ps(_mm256_loadu_ps(s.nx.data() + q), perm));
        _mm256_storeu_ps(ny.data() + count,
                         _mm256_permutevar8x32_ps(_mm256_loadu_ps(s.ny.data() + q), perm));
        _mm256_storeu_ps(nz.data() + count,
                         _mm256_permutevar8x32_ps(_mm256_loadu_ps(s.nz.data() + q), perm));
      }
      count += uint32_t(std::popcount(mask));
    }
  return count;
}

// The hits of p packed into `hits`, eight candidates at a time, the scalar expression's float
// operations lane by lane (and the sharp ones in sharp_ids).
template <bool kRow>
__attribute__((target("avx2"))) uint32_t Candidates::hits_avx2(const Sorted& s, uint32_t p) {
  const __m256 px = _mm256_set1_ps(s.x[p]), py = _mm256_set1_ps(s.y[p]),
               pz = _mm256_set1_ps(s.z[p]), pr = _mm256_set1_ps(s.r[p]);
  const __m256i self = _mm256_set1_epi32(int(s.id[p]));
  const __m256 pnx = _mm256_set1_ps(sharp ? s.nx[p] : 0), pny = _mm256_set1_ps(sharp ? s.ny[p] : 0),
               pnz = _mm256_set1_ps(sharp ? s.nz[p] : 0), w_s = _mm256_set1_ps(threshold);
  uint32_t m = 0;
  for (uint32_t j = 0; j < size; j += 8) {
    const __m256 dx = _mm256_sub_ps(px, _mm256_loadu_ps(x.data() + j));
    const __m256 dy = _mm256_sub_ps(py, _mm256_loadu_ps(y.data() + j));
    const __m256 dz = _mm256_sub_ps(pz, _mm256_loadu_ps(z.data() + j));
    const __m256 sum = _mm256_add_ps(pr, _mm256_loadu_ps(r.data() + j));
    const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                    _mm256_mul_ps(dz, dz));
    const __m256i ids = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(id.data() + j));
    const unsigned mask =
        unsigned(_mm256_movemask_ps(_mm256_cmp_ps(d2, _mm256_mul_ps(sum, sum), _CMP_LT_OQ))) &
        ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(ids, self))));
    m += uint32_t(std::popcount(mask));
    if constexpr (!kRow) continue;
    const __m256i perm = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(int64_t(kLaneCompress[mask])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(hits.data() + m - std::popcount(mask)),
                        _mm256_permutevar8x32_epi32(ids, perm));
    if (sharp && mask != 0) {
      const __m256 w =
          _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(pnx, _mm256_loadu_ps(nx.data() + j)),
                                      _mm256_mul_ps(pny, _mm256_loadu_ps(ny.data() + j))),
                        _mm256_mul_ps(pnz, _mm256_loadu_ps(nz.data() + j)));
      add_sharp(mask & ~unsigned(_mm256_movemask_ps(_mm256_cmp_ps(w, w_s, _CMP_GE_OQ))), j);
    }
  }
  return m;
}

// hits[0, m) ascending, in `sorted` (rank_sort_avx2).
__attribute__((target("avx2"))) std::span<const uint32_t> Candidates::sorted_avx2(uint32_t m) {
  rank_sort_avx2(hits.data(), m, sorted.data());
  return {sorted.data(), m};
}

template uint32_t Candidates::hits_avx2<true>(const Sorted&, uint32_t);
template uint32_t Candidates::hits_avx2<false>(const Sorted&, uint32_t);

}  // namespace splatkit::graph::overlap
#endif
