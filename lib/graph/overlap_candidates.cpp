#include "graph/overlap_candidates.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace splatkit::graph::overlap {

// False when the cell has no small splat.
bool Candidates::gather(const Sorted& s, std::size_t c, const Runs& runs) {
  const float R = s.small_radius;
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  float r_cell = -1;
  for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
    if (!(s.r[p] <= R)) continue;
    const float v[3] = {s.x[p], s.y[p], s.z[p]};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
    r_cell = std::max(r_cell, s.r[p]);
  }
  if (r_cell < 0) return false;
  std::size_t total = 0;
  for (const auto& [a, b] : runs) total += b - a;
  if (x.size() < total + 16) {
    for (auto* v : {&x, &y, &z, &r}) v->resize(total + 16);
    if (sharp)
      for (auto* v : {&nx, &ny, &nz}) v->resize(total + 16);
    id.resize(total + 16);
    hits.resize(total + 16);
    sorted.resize(total + 16);
  }
  uint32_t count = 0;
#if defined(__x86_64__)
  if (simd == SimdLevel::kAvx512) {
    count = copy_avx512(s, runs, lo, hi, r_cell);
  } else if (simd == SimdLevel::kAvx2) {
    count = copy_avx2(s, runs, lo, hi, r_cell);
  } else
#endif
  {
    for (const auto& [a, b] : runs)
      for (uint32_t q = a; q < b; ++q) {
        const float qx = s.x[q], qy = s.y[q], qz = s.z[q], qr = s.r[q];
        x[count] = qx, y[count] = qy, z[count] = qz, r[count] = qr, id[count] = s.id[q];
        if (sharp) nx[count] = s.nx[q], ny[count] = s.ny[q], nz[count] = s.nz[q];
        const float gx = std::max(std::max(lo[0] - qx, qx - hi[0]), 0.0f);
        const float gy = std::max(std::max(lo[1] - qy, qy - hi[1]), 0.0f);
        const float gz = std::max(std::max(lo[2] - qz, qz - hi[2]), 0.0f);
        const float sum = r_cell + qr;
        count += (gx * gx + gy * gy + gz * gz < sum * sum) & (qr <= R);
      }
  }
  // 16 padding entries (there is room), of which the ones up to a multiple of 16 are used.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::fill_n(x.data() + count, 16, nan);
  std::fill_n(y.data() + count, 16, nan);
  std::fill_n(z.data() + count, 16, nan);
  std::fill_n(r.data() + count, 16, nan);
  std::fill_n(id.data() + count, 16, 0u);
  size = (count + 15) & ~15u;
  return true;
}

// The neighbours of small splat p among the candidates, ascending; with sharp edges, the
// sharp ones also in sharp_ids.
std::span<const uint32_t> Candidates::row(const Sorted& s, uint32_t p) {
  sharp_ids.clear();
#if defined(__x86_64__)
  if (simd == SimdLevel::kAvx512) {
    const uint32_t m = row_avx512(s, p);
    if (m <= 16) return {sorted.data(), m};
  }
  if (simd >= SimdLevel::kAvx2) {
    sharp_ids.clear();  // a part of the row may be there from row_avx512
    const uint32_t m = hits_avx2<true>(s, p);
    if (m <= kRankLimit) return sorted_avx2(m);
    std::sort(hits.begin(), hits.begin() + m);
    return {hits.data(), m};
  }
#endif
  const uint32_t m = hits_portable<true>(s, p);
  std::sort(hits.begin(), hits.begin() + m);
  return {hits.data(), m};
}

// The number of neighbours of small splat p (sorted position) among the candidates.
uint32_t Candidates::count(const Sorted& s, uint32_t p) {
#if defined(__x86_64__)
  if (simd == SimdLevel::kAvx512) return count_avx512(s, p);
  if (simd == SimdLevel::kAvx2) return hits_avx2<false>(s, p);
#endif
  return hits_portable<false>(s, p);
}

// kRow: the hits in `hits` (and the sharp ones in sharp_ids); else only their number.
template <bool kRow>
uint32_t Candidates::hits_portable(const Sorted& s, uint32_t p) {
  const float px = s.x[p], py = s.y[p], pz = s.z[p], pr = s.r[p];
  const uint32_t self = s.id[p];
  uint32_t m = 0;
  for (uint32_t j = 0; j < size; ++j) {
    const float dx = px - x[j], dy = py - y[j], dz = pz - z[j];
    const float sum = pr + r[j];
    hits[m] = id[j];
    const bool hit = (dx * dx + dy * dy + dz * dz < sum * sum) & (id[j] != self);
    if (kRow && hit && sharp && !(s.nx[p] * nx[j] + s.ny[p] * ny[j] + s.nz[p] * nz[j] >= threshold))
      sharp_ids.push_back(id[j]);
    m += hit;
  }
  return m;
}

// Appends to sharp_ids the ids of candidates j + l for the bits l of `lanes`.
void Candidates::add_sharp(unsigned lanes, std::size_t j) {
  for (; lanes != 0; lanes &= lanes - 1) sharp_ids.push_back(id[j + std::countr_zero(lanes)]);
}

}  // namespace splatkit::graph::overlap
