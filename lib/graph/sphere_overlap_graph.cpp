#include "graph/sphere_overlap_graph.h"

#include <tbb/parallel_for.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/lane_compress.h"
#include "splatkit/rank_sort_avx2.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kCellBlock = 1024;  // cells per task
constexpr std::size_t kPad = 16;         // spare entries after the sorted arrays, for 16-wide loads
constexpr std::size_t kChunk = 1 << 16;  // splats per task of the simple parallel loops
// Splats ahead (in cell order) whose row offset is prefetched: the rows are far apart in memory.
constexpr std::size_t kAhead = 16;
constexpr std::size_t kMaxBig = 8192;
constexpr double kMaxBigRowsPerSplat = 8;  // budget of the big splats' cell-row scans
constexpr uint64_t kMaxCellsPerAxis = (uint64_t{1} << 21) - 3;  // keys stay below 2^63
// Cells are this much larger than 2 R, so float rounding of the cell coordinates or of the
// distance test can never put two overlapping small splats two cells apart.
constexpr double kCellMargin = 1e-5;

struct Grid {
  double lo[3];
  double inv_cell;
  uint64_t cells[3];  // cells per axis, without the padding layer on each side
  uint64_t nx, ny;    // padded sizes of x and y, for keys

  // Padded cell coordinate (1 .. cells[a]) of a coordinate along axis a, clamped.
  uint64_t coord(int a, double v) const {
    const double c = std::floor((v - lo[a]) * inv_cell);
    if (!(c >= 0)) return 1;
    return std::min<uint64_t>(uint64_t(c), cells[a] - 1) + 1;
  }
  uint64_t key(uint64_t x, uint64_t y, uint64_t z) const { return (z * ny + y) * nx + x; }
  uint64_t key_of(const Vec3f& p) const { return key(coord(0, p.x), coord(1, p.y), coord(2, p.z)); }
};

// Splats in cell order, structure of arrays, and the cells.
struct Sorted {
  std::vector<float> x, y, z, r;     // padded with kPad zeros for 16-wide loads
  std::vector<float> nx, ny, nz;     // the normals, when sharp edges are marked (also padded)
  std::vector<uint32_t> id;          // original index (also padded)
  std::size_t n = 0;                 // splats
  std::vector<uint64_t> cell_key;    // one per non-empty cell, ascending
  std::vector<uint32_t> cell_start;  // first splat of each cell, plus the count at the end
  float small_radius = 0;            // R: radii above it are big
};

void check(std::span<const Vec3f> positions, std::span<const float> radii) {
  if (radii.size() != positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one radius per position");
  if (positions.size() > std::size_t{0xFFFFFFFEu})
    throw std::invalid_argument("sphere_overlap_graph: more than 2^32 - 2 splats");
  auto bad = [&](std::size_t i) {
    const Vec3f& p = positions[i];
    return !(radii[i] >= 0) || !std::isfinite(radii[i]) || !std::isfinite(p.x) ||
           !std::isfinite(p.y) || !std::isfinite(p.z);
  };
  // The first bad splat, found in parallel chunks (the same one for any thread count).
  const std::size_t n = positions.size(), chunks = chunk_count(n, kChunk);
  std::vector<std::size_t> first_bad(chunks, n);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (bad(i)) {
        first_bad[c] = i;
        return;
      }
  });
  std::size_t i = n;
  for (std::size_t f : first_bad) i = std::min(i, f);
  if (i == n) return;
  if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
    throw std::invalid_argument("sphere_overlap_graph: radii must be finite and >= 0");
  throw Error(ErrorKind::kBadInput, "splat " + std::to_string(i) + " has a non-finite coordinate");
}

// R: the 99.9th percentile of the radii. Spacing-based radii are alike, but the largest ones
// (splats at the rims of sampling cells) can be a third larger than the rest, and the cell size
// (2 R) sets how many candidates each splat tests: the largest 0.1 % are cheaper as big splats.
float small_radius(std::span<const float> radii) {
  // From a sample of at most 2^16 radii: R only sets the cell size (any R gives the same graph).
  const std::size_t step = std::max<std::size_t>(1, radii.size() >> 16);
  std::vector<float> copy;
  for (std::size_t i = 0; i < radii.size(); i += step) copy.push_back(radii[i]);
  auto q = copy.begin() + std::ptrdiff_t(copy.size() * 999 / 1000);
  std::nth_element(copy.begin(), q, copy.end());
  return *q;
}

Grid make_grid(std::span<const Vec3f> positions, float r_small) {
  Grid g;
  double hi[3];
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = HUGE_VAL;
    hi[a] = -HUGE_VAL;
  }
  // The bounding box from parallel chunks' boxes (min and max are exact: any order).
  const std::size_t n = positions.size(), chunks = chunk_count(n, kChunk);
  std::vector<std::array<double, 6>> box(chunks);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::array<double, 6> b = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t i = begin; i < end; ++i) {
      const double v[3] = {positions[i].x, positions[i].y, positions[i].z};
      for (int a = 0; a < 3; ++a) {
        b[a] = std::min(b[a], v[a]);
        b[a + 3] = std::max(b[a + 3], v[a]);
      }
    }
    box[c] = b;
  });
  for (const auto& b : box)
    for (int a = 0; a < 3; ++a) {
      g.lo[a] = std::min(g.lo[a], b[a]);
      hi[a] = std::max(hi[a], b[a + 3]);
    }
  double cell = 2.0 * r_small * (1 + kCellMargin);
  const double extent = std::max({hi[0] - g.lo[0], hi[1] - g.lo[1], hi[2] - g.lo[2]});
  cell = std::max(cell, extent / double(kMaxCellsPerAxis) * (1 + kCellMargin));
  g.inv_cell = 1 / cell;
  for (int a = 0; a < 3; ++a) g.cells[a] = uint64_t(std::floor((hi[a] - g.lo[a]) * g.inv_cell)) + 1;
  g.nx = g.cells[0] + 2;
  g.ny = g.cells[1] + 2;
  return g;
}

// Stable LSD radix sort of (key, index) by key, 11 bits per pass.
void radix_sort(std::vector<uint64_t>& keys, std::vector<uint32_t>& ids, uint64_t max_key) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  std::vector<uint64_t> k2(keys.size());
  std::vector<uint32_t> i2(ids.size());
  for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += kBits) {
    std::vector<std::size_t> start(kBuckets + 1, 0);
    for (uint64_t k : keys) ++start[((k >> shift) & (kBuckets - 1)) + 1];
    for (std::size_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    for (std::size_t e = 0; e < keys.size(); ++e) {
      const std::size_t to = start[(keys[e] >> shift) & (kBuckets - 1)]++;
      k2[to] = keys[e];
      i2[to] = ids[e];
    }
    keys.swap(k2);
    ids.swap(i2);
  }
}

// v.resize(size) for a new, large v: the kernel maps the pages in parallel chunks first (as huge
// pages where it gives them), so the zeroing in resize does not fault them in one at a time on
// one thread (a fresh page costs more than writing it; the arrays here are tens of MB). The
// madvise calls are hints only: what stays unmapped is faulted in on first use.
template <class T>
void sized_in_parallel(std::vector<T>& v, std::size_t size) {
  v.reserve(size);
#if defined(MADV_POPULATE_WRITE)
  constexpr std::size_t kPage = 4096, kBytes = std::size_t{1} << 22;  // per madvise call
  const auto begin = (reinterpret_cast<uintptr_t>(v.data()) + kPage - 1) & ~(kPage - 1);
  const auto end = (reinterpret_cast<uintptr_t>(v.data() + size)) & ~(kPage - 1);
  if (end > begin) {
#if defined(MADV_HUGEPAGE)
    // Only whole 2 MB pages inside the vector: the hint stays on the range after it is freed.
    constexpr uintptr_t kHuge = uintptr_t{1} << 21;
    const uintptr_t huge_begin = (begin + kHuge - 1) & ~(kHuge - 1), huge_end = end & ~(kHuge - 1);
    if (huge_end > huge_begin)
      madvise(reinterpret_cast<void*>(huge_begin), huge_end - huge_begin, MADV_HUGEPAGE);
#endif
    tbb::parallel_for(uintptr_t{0}, (end - begin + kBytes - 1) / kBytes, [&](uintptr_t c) {
      const uintptr_t from = begin + c * kBytes, to = std::min(end, from + kBytes);
      madvise(reinterpret_cast<void*>(from), to - from, MADV_POPULATE_WRITE);
    });
  }
#endif
  v.resize(size);
}

// Stable LSD radix sort of (key << 32 | index) by key (keys below 2^32), 11 bits per pass, in
// parallel: each fixed chunk of the input counts its keys, and its share of every bucket starts
// after the earlier chunks' shares, so the result is the serial one for any thread count.
void radix_sort_packed(std::vector<uint64_t>& items, uint64_t max_key) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  const std::size_t n = items.size(), chunks = chunk_count(n, kChunk);
  std::vector<uint64_t> other;
  sized_in_parallel(other, n);
  std::vector<std::size_t> start(chunks * kBuckets);
  for (int shift = 32; shift < 64 && (max_key >> (shift - 32)) != 0; shift += kBits) {
    auto bucket = [shift](uint64_t v) { return std::size_t(v >> shift) & (kBuckets - 1); };
    for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
      std::size_t* count = start.data() + c * kBuckets;
      std::fill(count, count + kBuckets, 0);
      for (std::size_t e = begin; e < end; ++e) ++count[bucket(items[e])];
    });
    std::size_t at = 0;
    for (std::size_t b = 0; b < kBuckets; ++b)
      for (std::size_t c = 0; c < chunks; ++c) {
        const std::size_t count = start[c * kBuckets + b];
        start[c * kBuckets + b] = at;
        at += count;
      }
    for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
      std::size_t* to = start.data() + c * kBuckets;
      for (std::size_t e = begin; e < end; ++e) other[to[bucket(items[e])]++] = items[e];
    });
    items.swap(other);
  }
}

// s.cell_key and s.cell_start from the sorted keys key(0 .. n - 1), in parallel over fixed
// chunks: each counts the cells that start in it, then writes them after the earlier chunks'.
template <class Key>
void find_cells(std::size_t n, Key&& key, Sorted& s) {
  const std::size_t chunks = chunk_count(n, kChunk);
  auto starts = [&](std::size_t k) { return k == 0 || key(k) != key(k - 1); };
  std::vector<std::size_t> first(chunks + 1, 0);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) first[c + 1] += starts(k);
  });
  for (std::size_t c = 0; c < chunks; ++c) first[c + 1] += first[c];
  s.cell_key.resize(first[chunks]);
  s.cell_start.resize(first[chunks] + 1);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::size_t at = first[c];
    for (std::size_t k = begin; k < end; ++k)
      if (starts(k)) {
        s.cell_key[at] = key(k);
        s.cell_start[at++] = uint32_t(k);
      }
  });
  s.cell_start.back() = uint32_t(n);
}

// s.id: the original indices sorted by cell key (stable: by index within a cell); and the cells.
void sort_ids(std::span<const Vec3f> positions, const Grid& g, Sorted& s) {
  const std::size_t n = positions.size();
  const uint64_t max_key = g.key(g.cells[0] + 1, g.cells[1] + 1, g.cells[2] + 1);
  if (max_key >> 32 == 0) {
    std::vector<uint64_t> items;
    sized_in_parallel(items, n);
    tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
      for (std::size_t i = b; i < std::min(n, b + 65536); ++i)
        items[i] = g.key_of(positions[i]) << 32 | i;
    });
    radix_sort_packed(items, max_key);
    sized_in_parallel(s.id, n + kPad);
    tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
      for (std::size_t k = b; k < std::min(n, b + 65536); ++k) s.id[k] = uint32_t(items[k]);
    });
    find_cells(
        n, [&](std::size_t k) { return items[k] >> 32; }, s);
    return;
  }
  std::vector<uint64_t> keys(n);
  s.id.resize(n);
  tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
    for (std::size_t i = b; i < std::min(n, b + 65536); ++i) {
      keys[i] = g.key_of(positions[i]);
      s.id[i] = uint32_t(i);
    }
  });
  radix_sort(keys, s.id, max_key);
  s.id.resize(n + kPad);
  find_cells(
      n, [&](std::size_t k) { return keys[k]; }, s);
}

Sorted sort_by_cell(std::span<const Vec3f> positions, std::span<const float> radii,
                    std::span<const Vec3f> normals, const Grid& g, float r_small) {
  const std::size_t n = positions.size();
  Sorted s;
  sort_ids(positions, g, s);
  s.small_radius = r_small;
  s.n = n;
  for (auto* v : {&s.x, &s.y, &s.z, &s.r}) sized_in_parallel(*v, n + kPad);
  if (!normals.empty())
    for (auto* v : {&s.nx, &s.ny, &s.nz}) sized_in_parallel(*v, n + kPad);
  tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
    for (std::size_t k = b; k < std::min(n, b + 65536); ++k) {
      const Vec3f& p = positions[s.id[k]];
      s.x[k] = p.x;
      s.y[k] = p.y;
      s.z[k] = p.z;
      s.r[k] = radii[s.id[k]];
      if (!normals.empty()) {
        const Vec3f& v = normals[s.id[k]];
        s.nx[k] = v.x;
        s.ny[k] = v.y;
        s.nz[k] = v.z;
      }
    }
  });
  return s;
}

// Candidates of one cell: up to 9 runs [begin, end) of sorted splats.
using Runs = std::array<std::pair<uint32_t, uint32_t>, 9>;

#if defined(__x86_64__)
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

// Rows up to this long are sorted by ranking (quadratic, branch-free), longer ones by std::sort.
constexpr uint32_t kRankLimit = 64;
#endif

// The small splats that can overlap a small splat of one cell, copied together: those of the 27
// surrounding cells whose distance to the bounding box of the cell's small splats is below
// r_cell + r_q (r_cell their largest radius). For a splat p of the cell every splat left out has
// d² >= (r_p + r_q)²: float subtraction, squares and sums are monotonic, so the box distance
// computed like the pair's distance is never larger. Padded with NaN coordinates (never a hit)
// to a multiple of 16.
struct Candidates {
  std::vector<float> x, y, z, r;
  std::vector<float> nx, ny, nz;  // with sharp edges: the normals
  std::vector<uint32_t> id;
  std::vector<uint32_t> hits;       // one row before sorting
  std::vector<uint32_t> sorted;     // the row sorted (16 spare slots)
  std::vector<uint32_t> sharp_ids;  // the row's sharp neighbours, in no order (with sharp edges)
  OverlapSimd simd;                 // the vector code in use
  bool sharp = false;               // find the sharp edges (the sorted splats have normals)
  float threshold = 0;              // an edge is sharp iff !(n_i·n_j >= threshold)
  uint32_t size = 0;

  // False when the cell has no small splat.
  bool gather(const Sorted& s, std::size_t c, const Runs& runs) {
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
    if (simd == OverlapSimd::kAvx512) {
      count = copy_avx512(s, runs, lo, hi, r_cell);
    } else if (simd == OverlapSimd::kAvx2) {
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
  std::span<const uint32_t> row(const Sorted& s, uint32_t p) {
    sharp_ids.clear();
#if defined(__x86_64__)
    if (simd == OverlapSimd::kAvx512) {
      const uint32_t m = row_avx512(s, p);
      if (m <= 16) return {sorted.data(), m};
    }
    if (simd >= OverlapSimd::kAvx2) {
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
  uint32_t count(const Sorted& s, uint32_t p) {
#if defined(__x86_64__)
    if (simd == OverlapSimd::kAvx512) return count_avx512(s, p);
    if (simd == OverlapSimd::kAvx2) return hits_avx2<false>(s, p);
#endif
    return hits_portable<false>(s, p);
  }

  // kRow: the hits in `hits` (and the sharp ones in sharp_ids); else only their number.
  template <bool kRow>
  uint32_t hits_portable(const Sorted& s, uint32_t p) {
    const float px = s.x[p], py = s.y[p], pz = s.z[p], pr = s.r[p];
    const uint32_t self = s.id[p];
    uint32_t m = 0;
    for (uint32_t j = 0; j < size; ++j) {
      const float dx = px - x[j], dy = py - y[j], dz = pz - z[j];
      const float sum = pr + r[j];
      hits[m] = id[j];
      const bool hit = (dx * dx + dy * dy + dz * dz < sum * sum) & (id[j] != self);
      if (kRow && hit && sharp &&
          !(s.nx[p] * nx[j] + s.ny[p] * ny[j] + s.nz[p] * nz[j] >= threshold))
        sharp_ids.push_back(id[j]);
      m += hit;
    }
    return m;
  }

  // Appends to sharp_ids the ids of candidates j + l for the bits l of `lanes`.
  void add_sharp(unsigned lanes, std::size_t j) {
    for (; lanes != 0; lanes &= lanes - 1) sharp_ids.push_back(id[j + std::countr_zero(lanes)]);
  }

#if defined(__x86_64__)
  // gather's copy and test, eight splats at a time (the arrays are padded; lanes past a run's
  // end are masked off).
  __attribute__((target("avx2"))) uint32_t copy_avx2(const Sorted& s, const Runs& runs,
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
  __attribute__((target("avx2"))) uint32_t hits_avx2(const Sorted& s, uint32_t p) {
    const __m256 px = _mm256_set1_ps(s.x[p]), py = _mm256_set1_ps(s.y[p]),
                 pz = _mm256_set1_ps(s.z[p]), pr = _mm256_set1_ps(s.r[p]);
    const __m256i self = _mm256_set1_epi32(int(s.id[p]));
    const __m256 pnx = _mm256_set1_ps(sharp ? s.nx[p] : 0),
                 pny = _mm256_set1_ps(sharp ? s.ny[p] : 0),
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

  // (GCC 12's AVX-512 headers trip -Wuninitialized on their own undefined-vector placeholders,
  // GCC bug 105593.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  // The number of hits of p, sixteen candidates at a time (row_avx512's test).
  __attribute__((target("avx512f"))) uint32_t count_avx512(const Sorted& s, uint32_t p) {
    const __m512 px = _mm512_set1_ps(s.x[p]), py = _mm512_set1_ps(s.y[p]),
                 pz = _mm512_set1_ps(s.z[p]), pr = _mm512_set1_ps(s.r[p]);
    const __m512i self = _mm512_set1_epi32(int(s.id[p]));
    uint32_t m = 0;
    for (std::size_t j = 0; j < size; j += 16) {
      const __m512 dx = _mm512_sub_ps(px, _mm512_loadu_ps(x.data() + j));
      const __m512 dy = _mm512_sub_ps(py, _mm512_loadu_ps(y.data() + j));
      const __m512 dz = _mm512_sub_ps(pz, _mm512_loadu_ps(z.data() + j));
      const __m512 sum = _mm512_add_ps(pr, _mm512_loadu_ps(r.data() + j));
      const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                      _mm512_mul_ps(dz, dz));
      const __mmask16 hit = _mm512_cmp_ps_mask(d2, _mm512_mul_ps(sum, sum), _CMP_LT_OQ) &
                            ~_mm512_cmpeq_epi32_mask(_mm512_loadu_si512(id.data() + j), self);
      m += uint32_t(std::popcount(unsigned(hit)));
    }
    return m;
  }

  // The hits of p ascending in `sorted` (16 slots written), sixteen candidates at a time, the
  // scalar expression's float operations lane by lane (and the sharp ones in sharp_ids): each
  // step's hits are compressed and appended in one register, then sorted there by the bitonic
  // network, so that no row goes through memory before it is sorted. Returns the count, or 17
  // when p has more than 16 hits (then `sorted` holds nothing useful).
  __attribute__((target("avx512f"))) uint32_t row_avx512(const Sorted& s, uint32_t p) {
    const __m512 px = _mm512_set1_ps(s.x[p]), py = _mm512_set1_ps(s.y[p]),
                 pz = _mm512_set1_ps(s.z[p]), pr = _mm512_set1_ps(s.r[p]);
    const __m512i self = _mm512_set1_epi32(int(s.id[p]));
    const __m512 pnx = _mm512_set1_ps(sharp ? s.nx[p] : 0),
                 pny = _mm512_set1_ps(sharp ? s.ny[p] : 0),
                 pnz = _mm512_set1_ps(sharp ? s.nz[p] : 0), w_s = _mm512_set1_ps(threshold);
    __m512i row = _mm512_set1_epi32(-1);  // 2^32 - 1 in the empty lanes: sorted last
    uint32_t m = 0;
    for (std::size_t j = 0; j < size; j += 16) {
      const __m512 dx = _mm512_sub_ps(px, _mm512_loadu_ps(x.data() + j));
      const __m512 dy = _mm512_sub_ps(py, _mm512_loadu_ps(y.data() + j));
      const __m512 dz = _mm512_sub_ps(pz, _mm512_loadu_ps(z.data() + j));
      const __m512 sum = _mm512_add_ps(pr, _mm512_loadu_ps(r.data() + j));
      const __m512 d2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                      _mm512_mul_ps(dz, dz));
      const __m512i ids = _mm512_loadu_si512(id.data() + j);
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
  __attribute__((target("avx512f"))) uint32_t copy_avx512(const Sorted& s, const Runs& runs,
                                                          const float lo[3], const float hi[3],
                                                          float r_cell) {
    const __m512 lx = _mm512_set1_ps(lo[0]), ly = _mm512_set1_ps(lo[1]), lz = _mm512_set1_ps(lo[2]);
    const __m512 hx = _mm512_set1_ps(hi[0]), hy = _mm512_set1_ps(hi[1]), hz = _mm512_set1_ps(hi[2]);
    const __m512 rc = _mm512_set1_ps(r_cell), big = _mm512_set1_ps(s.small_radius);
    const __m512 zero = _mm512_setzero_ps();
    uint32_t count = 0;
    for (const auto& [a, b] : runs)
      for (std::size_t q = a; q < b; q += 16) {
        const __m512 qx = _mm512_loadu_ps(s.x.data() + q), qy = _mm512_loadu_ps(s.y.data() + q),
                     qz = _mm512_loadu_ps(s.z.data() + q), qr = _mm512_loadu_ps(s.r.data() + q);
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
        _mm512_storeu_ps(x.data() + count, _mm512_maskz_compress_ps(keep, qx));
        _mm512_storeu_ps(y.data() + count, _mm512_maskz_compress_ps(keep, qy));
        _mm512_storeu_ps(z.data() + count, _mm512_maskz_compress_ps(keep, qz));
        _mm512_storeu_ps(r.data() + count, _mm512_maskz_compress_ps(keep, qr));
        _mm512_storeu_si512(id.data() + count,
                            _mm512_maskz_compress_epi32(keep, _mm512_loadu_si512(s.id.data() + q)));
        if (sharp) {
          _mm512_storeu_ps(nx.data() + count,
                           _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(s.nx.data() + q)));
          _mm512_storeu_ps(ny.data() + count,
                           _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(s.ny.data() + q)));
          _mm512_storeu_ps(nz.data() + count,
                           _mm512_maskz_compress_ps(keep, _mm512_loadu_ps(s.nz.data() + q)));
        }
        count += uint32_t(std::popcount(unsigned(keep)));
      }
    return count;
  }
#pragma GCC diagnostic pop

  // hits[0, m) ascending, in `sorted` (rank_sort_avx2).
  __attribute__((target("avx2"))) std::span<const uint32_t> sorted_avx2(uint32_t m) {
    rank_sort_avx2(hits.data(), m, sorted.data());
    return {sorted.data(), m};
  }
#endif
};

// Calls fn(c, runs) for the cells c0 .. c1 - 1 in order, runs = the splats of the 27 cells
// around c: 9 runs of 3 consecutive keys, each at a fixed key offset from the cell's own key, so
// one forward-only cursor per run finds them.
template <class Fn>
void for_each_cell(const Sorted& s, const Grid& g, std::size_t c0, std::size_t c1, Fn&& fn) {
  const std::vector<uint64_t>& keys = s.cell_key;
  const std::size_t cells = keys.size();
  std::array<int64_t, 9> offset;
  std::array<std::size_t, 9> cursor;
  for (int k = 0; k < 9; ++k) {
    const int64_t dy = k % 3 - 1, dz = k / 3 - 1;
    offset[k] = (dz * int64_t(g.ny) + dy) * int64_t(g.nx) - 1;
    cursor[k] = std::size_t(
        std::lower_bound(keys.begin(), keys.end(), uint64_t(int64_t(keys[c0]) + offset[k])) -
        keys.begin());
  }
  Runs runs;
  for (std::size_t c = c0; c < c1; ++c) {
    for (int k = 0; k < 9; ++k) {
      const uint64_t lo = uint64_t(int64_t(keys[c]) + offset[k]), hi = lo + 2;
      std::size_t& cur = cursor[k];
      while (cur < cells && keys[cur] < lo) ++cur;
      std::size_t end = cur;
      while (end < cells && keys[end] <= hi) ++end;
      runs[k] = {s.cell_start[cur], s.cell_start[end]};
    }
    fn(c, runs);
  }
}

// Neighbours of big splat b (sorted position): small splats in the cells within r_b + R, and
// every other big splat by a direct test. Original indices, ascending.
std::vector<uint32_t> big_row(const Sorted& s, const Grid& g, uint32_t b,
                              const std::vector<uint32_t>& bigs) {
  const float R = s.small_radius, rb = s.r[b];
  const double reach = (double(rb) + R) * (1 + kCellMargin);
  const double c[3] = {s.x[b], s.y[b], s.z[b]};
  uint64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = g.coord(a, c[a] - reach);
    hi[a] = g.coord(a, c[a] + reach);
  }
  std::vector<uint32_t> row;
  auto test = [&](uint32_t q) {
    const float dx = s.x[b] - s.x[q], dy = s.y[b] - s.y[q], dz = s.z[b] - s.z[q];
    const float sum = rb + s.r[q];
    if (dx * dx + dy * dy + dz * dz < sum * sum && q != b) row.push_back(s.id[q]);
  };
  for (uint64_t z = lo[2]; z <= hi[2]; ++z)
    for (uint64_t y = lo[1]; y <= hi[1]; ++y) {
      const uint64_t first = g.key(lo[0], y, z), last = g.key(hi[0], y, z);
      auto it = std::lower_bound(s.cell_key.begin(), s.cell_key.end(), first);
      for (; it != s.cell_key.end() && *it <= last; ++it) {
        const std::size_t cell = std::size_t(it - s.cell_key.begin());
        for (uint32_t q = s.cell_start[cell]; q < s.cell_start[cell + 1]; ++q)
          if (s.r[q] <= R) test(q);
      }
    }
  for (uint32_t q : bigs) test(q);
  std::sort(row.begin(), row.end());
  return row;
}

// The extra entries the big splats bring: (row << 32 | neighbour) in original indices, sorted;
// false when they would cost more than the budget.
bool big_pairs(const Sorted& s, const Grid& g, std::vector<uint64_t>& pairs) {
  const std::size_t n = s.n;
  const std::size_t chunks = chunk_count(n, kChunk);
  std::vector<std::vector<uint32_t>> chunk_bigs(chunks);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t p = begin; p < end; ++p)
      if (s.r[p] > s.small_radius) chunk_bigs[c].push_back(uint32_t(p));
  });
  std::vector<uint32_t> bigs;
  for (const auto& b : chunk_bigs) bigs.insert(bigs.end(), b.begin(), b.end());
  if (bigs.empty()) return true;
  if (bigs.size() > kMaxBig) return false;
  double rows = 0;
  for (uint32_t b : bigs) {
    const double cells = 2 * (double(s.r[b]) + s.small_radius) * g.inv_cell + 3;
    rows += cells * cells;
  }
  if (rows > kMaxBigRowsPerSplat * double(n)) return false;
  std::vector<std::vector<uint32_t>> found(bigs.size());
  tbb::parallel_for(std::size_t{0}, bigs.size(),
                    [&](std::size_t k) { found[k] = big_row(s, g, bigs[k], bigs); });
  std::vector<uint8_t> big_id(n, 0);
  for (uint32_t b : bigs) big_id[s.id[b]] = 1;
  for (std::size_t k = 0; k < bigs.size(); ++k) {
    const uint64_t b = s.id[bigs[k]];
    for (uint32_t q : found[k]) {
      pairs.push_back(b << 32 | q);
      // A big neighbour finds b by itself; a small one needs b in its row.
      if (!big_id[q]) pairs.push_back(uint64_t{q} << 32 | b);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return true;
}

// offsets[i] += offsets[i - 1] for all i, in parallel over fixed chunks (the same sums for any
// thread count: integer addition).
void prefix_sum(std::vector<uint64_t>& v) {
  const std::size_t chunks = chunk_count(v.size(), kChunk);
  std::vector<uint64_t> carry(chunks + 1, 0);
  for_each_chunk(v.size(), kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    uint64_t sum = 0;
    for (std::size_t i = begin; i < end; ++i) sum += v[i];
    carry[c + 1] = sum;
  });
  for (std::size_t c = 0; c < chunks; ++c) carry[c + 1] += carry[c];
  for_each_chunk(v.size(), kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    uint64_t sum = carry[c];
    for (std::size_t i = begin; i < end; ++i) v[i] = sum += v[i];
  });
}

// Writes row `id`: its small neighbours `base` merged with its entries in `pairs`.
void write_row(uint32_t id, std::span<const uint32_t> base, std::size_t extra,
               const std::vector<uint64_t>& pairs, uint32_t* out) {
  if (extra == 0) {
    for (uint32_t v : base) *out++ = v;  // rows are short: no memmove call
    return;
  }
  auto e = std::lower_bound(pairs.begin(), pairs.end(), uint64_t{id} << 32);
  auto b = base.begin();
  for (std::size_t left = extra; left > 0 || b != base.end();) {
    if (left > 0 && (b == base.end() || uint32_t(*e) < *b)) {
      *out++ = uint32_t(*e++);
      --left;
    } else {
      *out++ = *b++;
    }
  }
}

// The best vector code this CPU runs, up to `limit`.
OverlapSimd supported(OverlapSimd limit) {
#if defined(__x86_64__)
  static const OverlapSimd best = !cpu_has_avx2()                     ? OverlapSimd::kPortable
                                  : __builtin_cpu_supports("avx512f") ? OverlapSimd::kAvx512
                                                                      : OverlapSimd::kAvx2;
  return std::min(limit, best);
#else
  (void)limit;
  return OverlapSimd::kPortable;
#endif
}

// One edge flag per entry of row i, set where the edge is sharp (normals from the caller, in
// original order): for the rows the grid does not find by itself. Returns whether any is.
bool mark_sharp_row(uint32_t i, std::span<const uint32_t> row, const SharpEdges& sharp,
                    uint8_t* flags) {
  bool any = false;
  for (std::size_t k = 0; k < row.size(); ++k) {
    const bool is_sharp = !(dot(sharp.normals[i], sharp.normals[row[k]]) >= sharp.threshold);
    flags[k] = is_sharp ? sharp.flag : 0;
    any = any || is_sharp;
  }
  return any;
}

// marks.rows from per-chunk lists (any order of chunks): ascending.
void join_rows(const std::vector<std::vector<uint32_t>>& chunk_rows, SharpEdgeMarks& marks) {
  marks.rows.clear();
  for (const auto& r : chunk_rows) marks.rows.insert(marks.rows.end(), r.begin(), r.end());
  std::sort(marks.rows.begin(), marks.rows.end());
}

void mark_sharp_rows(const NeighborGraph& graph, const SharpEdges& sharp, SharpEdgeMarks& marks) {
  const std::size_t n = graph.num_points(), chunk = kChunk / 16;
  marks.flags.assign(graph.neighbors.size(), 0);
  std::vector<std::vector<uint32_t>> rows(chunk_count(n, chunk));
  for_each_chunk(n, chunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (mark_sharp_row(uint32_t(i), graph.row(i), sharp, marks.flags.data() + graph.offsets[i]))
        rows[c].push_back(uint32_t(i));
  });
  join_rows(rows, marks);
}

// The graph in two passes over the cells, so that no rows are stored twice: the row lengths
// (small neighbours plus the big splats' pairs) give the offsets, then each row is found again
// and written in place, merged with its pairs. With `sharp`, the marks are set as the rows are
// written.
NeighborGraph small_rows(const Sorted& s, const Grid& g, const std::vector<uint64_t>& pairs,
                         OverlapSimd simd, const SharpEdges* sharp, SharpEdgeMarks* marks) {
  const std::size_t n = s.n;
  const float R = s.small_radius;
  const std::size_t cells = s.cell_key.size(), blocks = (cells + kCellBlock - 1) / kCellBlock;
  // fn(b, c0, c1, candidates) for the blocks of cells, in parallel; the candidates carry the
  // normals when with_normals.
  auto for_each_block = [&](bool with_normals, auto&& fn) {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      Candidates cand;
      cand.simd = simd;
      cand.sharp = with_normals;
      cand.threshold = sharp ? sharp->threshold : 0;
      fn(b, b * kCellBlock, std::min(cells, (b + 1) * kCellBlock), cand);
    });
  };
  NeighborGraph graph;
  sized_in_parallel(graph.offsets, n + 1);
  graph.offsets[0] = 0;
  for_each_block(false, [&](std::size_t, std::size_t c0, std::size_t c1, Candidates& cand) {
    for_each_cell(s, g, c0, c1, [&](std::size_t c, const Runs& runs) {
      const bool any = cand.gather(s, c, runs);
      for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
        __builtin_prefetch(&graph.offsets[s.id[std::min<std::size_t>(p + kAhead, n - 1)]], 1);
        graph.offsets[std::size_t{s.id[p]} + 1] = any && s.r[p] <= R ? cand.count(s, p) : 0;
      }
    });
  });
  for (uint64_t pair : pairs) ++graph.offsets[(pair >> 32) + 1];
  prefix_sum(graph.offsets);
  sized_in_parallel(graph.neighbors, graph.offsets[n]);
  uint8_t* flags = nullptr;
  if (marks) {
    marks->flags.clear();
    sized_in_parallel(marks->flags, graph.offsets[n]);
    flags = marks->flags.data();
  }
  std::vector<std::vector<uint32_t>> sharp_rows(blocks);
  for_each_block(
      sharp != nullptr, [&](std::size_t b, std::size_t c0, std::size_t c1, Candidates& cand) {
        for_each_cell(s, g, c0, c1, [&](std::size_t c, const Runs& runs) {
          const bool any = cand.gather(s, c, runs);
          for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
            __builtin_prefetch(&graph.offsets[s.id[std::min<std::size_t>(p + kAhead, n - 1)]]);
            const uint64_t soon = graph.offsets[s.id[std::min<std::size_t>(p + kAhead / 4, n - 1)]];
            __builtin_prefetch(graph.neighbors.data() + soon, 1);
            const uint32_t id = s.id[p];
            const uint64_t at = graph.offsets[id], length = graph.offsets[std::size_t{id} + 1] - at;
            std::span<const uint32_t> row;
            if (any && s.r[p] <= R)
              row = cand.row(s, p);  // (and its sharp ids)
            else
              cand.sharp_ids.clear();
            // Both passes test with the same float operations; a row that grew would overrun.
            if (row.size() > length)
              throw std::logic_error("sphere_overlap_graph: a row differs between the passes");
            uint32_t* out = graph.neighbors.data() + at;
            write_row(id, row, length - row.size(), pairs, out);
            if (!flags) continue;
            bool any_sharp;
            if (length != row.size()) {  // merged with pairs: marked directly
              any_sharp = mark_sharp_row(id, {out, length}, *sharp, flags + at);
            } else {
              for (uint32_t j : cand.sharp_ids)  // (always in the row: found by the same test)
                flags[at + std::size_t(std::lower_bound(row.begin(), row.end(), j) - row.begin())] =
                    sharp->flag;
              any_sharp = !cand.sharp_ids.empty();
            }
            if (any_sharp) sharp_rows[b].push_back(id);
          }
        });
      });
  if (marks) join_rows(sharp_rows, *marks);
  return graph;
}

NeighborGraph overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                            OverlapSimd limit, const SharpEdges* sharp, SharpEdgeMarks* marks) {
  check(positions, radii);
  const std::size_t n = positions.size();
  // Graphs the grid does not build get their flags afterwards, from the caller's normals.
  auto marked = [&](NeighborGraph graph) {
    if (sharp) mark_sharp_rows(graph, *sharp, *marks);
    return graph;
  };
  if (n == 0) return marked(NeighborGraph{{0}, {}});
  const float r_small = small_radius(radii);
  if (!(r_small > 0)) {
    // All radii 0: (0 + 0)² is never > d². Otherwise almost all are 0 and a grid has no scale.
    if (*std::max_element(radii.begin(), radii.end()) == 0)
      return marked(NeighborGraph{std::vector<uint64_t>(n + 1, 0), {}});
    return marked(SpatialIndex(positions).sphere_overlaps(radii));
  }
  const Grid g = make_grid(positions, r_small);
  const Sorted s =
      sort_by_cell(positions, radii, sharp ? sharp->normals : std::span<const Vec3f>{}, g, r_small);
  std::vector<uint64_t> pairs;
  if (!big_pairs(s, g, pairs)) return marked(SpatialIndex(positions).sphere_overlaps(radii));
  return small_rows(s, g, pairs, supported(limit), sharp, marks);
}

}  // namespace

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   OverlapSimd limit) {
  return overlap_graph(positions, radii, limit, nullptr, nullptr);
}

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   const SharpEdges& sharp, SharpEdgeMarks& marks,
                                   OverlapSimd limit) {
  if (sharp.normals.size() != positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one normal per position");
  return overlap_graph(positions, radii, limit, &sharp, &marks);
}

}  // namespace splatkit::graph
