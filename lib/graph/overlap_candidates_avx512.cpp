// Candidates' AVX-512 path: copy and test sixteen splats at a time; a row of up to 16 is
// compressed and sorted in one register.
#include "graph/overlap_candidates.h"

#if defined(__x86_64__)
#include <immintrin.h>

#include <array>
#include <bit>
#include <cstdint>

namespace splatkit::graph::overlap {
namespace {

// The compare-exchange steps of a bitonic sort of 16 lanes: lane i meets lane i ^ distance and
// keeps the larger value where take_max has bit i (the upper lane of a pair in an ascending
// block of `size` lanes, the lower one in a descending block).
struct BitonicStep {
  int distance;
  uint16_t take_max;
};
constexpr std::array<BitonicStep, 10> kBitonic16 = [] {
  std::array<BitonicStep, 10> steps{};
  int k = 0;
  for (int size = 2; size <= 16; size *= 2)
    for (int distance = size / 2; distance > 0; distance /= 2) {
      uint16_t mask = 0;
      for (int i = 0; i < 16; ++i)
        if (((i & distance) != 0) == ((i & size) == 0)) mask = uint16_t(mask | 1u << i);
      steps[k++] = {distance, mask};
    }
  return steps;
}();

// One step of kBitonic16 with the cheapest shuffle that pairs lane i with lane i ^ D: within
// 128-bit lanes for D = 1, 2, across them for D = 4, 8.
template <int D>
__attribute__((target("avx512f"))) inline __m512i bitonic_step(__m512i v, uint16_t take_max) {
  __m512i other;
  if constexpr (D == 1) other = _mm512_shuffle_epi32(v, _MM_PERM_CDAB);
  if constexpr (D == 2) other = _mm512_shuffle_epi32(v, _MM_PERM_BADC);
  if constexpr (D == 4) other = _mm512_shuffle_i32x4(v, v, _MM_SHUFFLE(2, 3, 0, 1));
  if constexpr (D == 8) other = _mm512_shuffle_i32x4(v, v, _MM_SHUFFLE(1, 0, 3, 2));
  return _mm512_mask_blend_epi32(take_max, _mm512_min_epu32(v, other), _mm512_max_epu32(v, other));
}

// The 16 lanes of v ascending (as unsigned).
__attribute__((target("avx512f"))) inline __m512i sort16_avx512(__m512i v) {
  constexpr auto& k = kBitonic16;
  static_assert(k[0].distance == 1 && k[1].distance == 2 && k[2].distance == 1 &&
                k[3].distance == 4 && k[4].distance == 2 && k[5].distance == 1 &&
                k[6].distance == 8 && k[7].distance == 4 && k[8].distance == 2 &&
                k[9].distance == 1);
  v = bitonic_step<1>(v, k[0].take_max);
  v = bitonic_step<2>(v, k[1].take_max);
  v = bitonic_step<1>(v, k[2].take_max);
  v = bitonic_step<4>(v, k[3].take_max);
  v = bitonic_step<2>(v, k[4].take_max);
  v = bitonic_step<1>(v, k[5].take_max);
  v = bitonic_step<8>(v, k[6].take_max);
  v = bitonic_step<4>(v, k[7].take_max);
  v = bitonic_step<2>(v, k[8].take_max);
  return bitonic_step<1>(v, k[9].take_max);
}

}  // namespace

// (GCC 12's AVX-512 headers trip -Wuninitialized on their own undefined-vector placeholders,
// GCC bug 105593.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC's only
#endif
// The number of hits of p, sixteen candidates at a time (row_avx512's test).
__attribute__((target("avx512f"))) uint32_t Candidates::count_avx512(const Sorted& s, uint32_t p) {
  const __m512 px = _mm512_set1_ps(s.x[p]), py = _mm512_set1_ps(s.y[p]),
               pz = _mm512_set1_ps(s.z[p]), pr = _mm512_set1_ps(s.r[p]);
  const __m512i self = _mm512_set1_epi32(int(s.id[p]));
  const float *cx = x.data(), *cy = y.data(), *cz = z.data(), *cr = r.data();
  const uint32_t* cid = id.data();
  uint32_t m = 0;
  for (std::size_t j = 0; j < size; j += 16) {
    const __m512 dx = _mm512_sub_ps(px, _mm512_loadu_ps(cx + j));
    const __m512 dy = _mm512_sub_ps(py, _mm512_loadu_ps(cy + j));
    const __m512 dz = _mm512_sub_ps(pz, _mm512_loadu_ps(cz + j));
    const __m512 sum = _mm512_add_ps(pr, _mm512_loadu_ps(cr + j));
    const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                    _mm512_mul_ps(dz, dz));
    const __mmask16 hit = _mm512_cmp_ps_mask(d2, _mm512_mul_ps(sum, sum), _CMP_LT_OQ) &
                          ~_mm512_cmpeq_epi32_mask(_mm512_loadu_si512(cid + j), self);
    m += uint32_t(std::popcount(unsigned(hit)));
  }
  return m;
}

// The hits of p ascending in `sorted` (16 slots written), sixteen candidates at a time, the
// scalar expression's float operations lane by lane (and the sharp ones in sharp_ids): each
// step's hits are compressed and appended in one register, then sorted there by the bitonic
// network, so that no row goes through memory before it is sorted. Returns the count, or 17
// when p has more than 16 hits (then `sorted` holds nothing useful).
__attribute__((target("avx512f"))) uint32_t Candidates::row_avx512(const Sorted& s, uint32_t p) {
  const __m512 px = _mm512_set1_ps(s.x[p]), py = _mm512_set1_ps(s.y[p]),
               pz = _mm512_set1_ps(s.z[p]), pr = _mm512_set1_ps(s.r[p]);
  const __m512i self = _mm512_set1_epi32(int(s.id[p]));
  const __m512 pnx = _mm512_set1_ps(sharp ? s.nx[p] : 0), pny = _mm512_set1_ps(sharp ? s.ny[p] : 0),
               pnz = _mm512_set1_ps(sharp ? s.nz[p] : 0), w_s = _mm512_set1_ps(threshold);
  __m512i row = _mm512_set1_epi32(-1);  // 2^32 - 1 in the empty lanes: sorted last
  const float *cx = x.data(), *cy = y.data(), *cz = z.data(), *cr = r.data();
  const uint32_t* cid = id.data();
  uint32_t m = 0;
  for (std::size_t j = 0; j < size; j += 16) {
    const __m512 dx = _mm512_sub_ps(px, _mm512_loadu_ps(cx + j));
    const __m512 dy = _mm512_sub_ps(py, _mm512_loadu_ps(cy + j));
    const __m512 dz = _mm512_sub_ps(pz, _mm512_loadu_ps(cz + j));
    const __m512 sum = _mm512_add_ps(pr, _mm512_loadu_ps(cr + j));
    const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                    _mm512_mul_ps(dz, dz));
    const __m512i ids = _mm512_loadu_si512(cid + j);
    const __mmask16 hit = _mm512_cmp_ps_mask(d2, _mm512_mul_ps(sum, sum), _CMP_LT_OQ) &
                          ~_mm512_cmpeq_epi32_mask(ids, self);
    const uint32_t k = uint32_t(std::popcount(unsigned(hit)));
    if (m + k > 16) return 17;
    if (sharp && hit != 0) {
      const __m512 w =
          _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(pnx, _mm512_loadu_ps(nx.data() + j)),
                                      _mm512_mul_ps(pny, _mm512_loadu_ps(ny.data() + j))),
                        _mm512_mul_ps(pnz, _mm512_loadu_ps(nz.data() + j)));
      add_sharp(unsigned(hit & ~_mm512_cmp_ps_mask(w, w_s, _CMP_GE_OQ)), j);
    }
    row = _mm512_mask_expand_epi32(row, __mmask16(((1u << k) - 1) << m),
                                   _mm512_maskz_compress_epi32(hit, ids));
    m += k;
  }
  _mm512_storeu_si512(sorted.data(), sort16_avx512(row));
  return m;
}

// gather's copy and test, sixteen splats at a time (as copy_avx2), each compressed in a register
// and stored whole.
__attribute__((target("avx512f"))) uint32_t Candidates::copy_avx512(
    const Sorted& s, const Runs& runs, const float lo[3], const float hi[3], float r_cell) {
  const __m512 lx = _mm512_set1_ps(lo[0]), ly = _mm512_set1_ps(lo[1]), lz = _mm512_set1_ps(lo[2]);
  const __m512 hx = _mm512_set1_ps(hi[0]), hy = _mm512_set1_ps(hi[1]), hz = _mm512_set1_ps(hi[2]);
  const __m512 rc = _mm512_set1_ps(r_cell), big = _mm512_set1_ps(s.small_radius);
  const __m512 zero = _mm512_setzero_ps();
  // (The arrays' pointers held apart: the stores would otherwise reload them every step.)
  const float *sx = s.x.data(), *sy = s.y.data(), *sz = s.z.data(), *sr = s.r.data();
  const float *snx = s.nx.data(), *sny = s.ny.data(), *snz = s.nz.data();
  const uint32_t* sid = s.id.data();
  float *ox = x.data(), *oy = y.data(), *oz = z.data(), *orad = r.data();
  float *onx = nx.data(), *ony = ny.data(), *onz = nz.data();
  uint32_t* oid = id.data();
  const bool with_normals = sharp;
  uint32_t count = 0;
  for (const auto& [a, b] : runs)
    for (std::size_t q = a; q < b; q += 16) {
      const __m512 qx = _mm512_loadu_ps(sx + q), qy = _mm512_loadu_ps(sy + q),
                   qz = _mm512_loadu_ps(sz + q), qr = _mm512_loadu_ps(sr + q);
      const __m512 gx =
          _mm512_max_ps(_mm512_max_ps(_mm512_sub_ps(lx, qx), _mm512_sub_ps(qx, hx)), zero);
      const __m512 gy =
          _mm512_max_ps(_mm512_max_ps(_mm512_sub_ps(ly, qy), _mm512_sub_ps(qy, hy)), zero);
      const __m512 gz =
          _mm512_max_ps(_mm512_max_ps(_mm512_sub_ps(lz, qz), _mm512_sub_ps(qz, hz)), zero);
      const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(gx, gx), _mm512_mul_ps(gy, gy)),
                                      _mm512_mul_ps(gz, gz));
      const __m512 sum = _mm512_add_ps(rc, qr);
      const __mmask16 lanes = b - q >= 16 ? 0xFFFF : __mmask16((1u << (b - q)) - 1);
      const __mmask16 keep = _mm512_cmp_ps_mask(d2, _mm512_mul_ps(sum, sum), _CMP_LT_OQ) &
                             _mm512_cmp_ps_mask(qr, big, _CMP_LE_OQ) & lanes;
      _mm512_storeu_ps(ox + count, _mm512_maskz_compress_ps(keep, qx));
      _mm512_storeu_ps(oy + count, _mm512_maskz_compress_ps(keep, qy));
      _mm512_storeu_ps(oz + count, _mm512_maskz_compress_ps(keep, qz));
      _mm512_storeu_ps(orad + count, _mm512_maskz_compress_ps(keep, qr));
      _mm512_storeu_si512(oid + count,
                          _mm512_maskz_compress_epi32(keep, _mm512_loadu_si512(sid + q)));
      if (with_normals) {
        _mm512_storeu_ps(onx + count, _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(snx + q)));
        _mm512_storeu_ps(ony + count, _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(sny + q)));
        _mm512_storeu_ps(onz + count, _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(snz + q)));
      }
      count += uint32_t(std::popcount(unsigned(keep)));
    }
  return count;
}
#pragma GCC diagnostic pop

}  // namespace splatkit::graph::overlap
#endif
