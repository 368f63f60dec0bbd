#include "graph/overlap_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/sized_in_parallel.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::graph::overlap {
namespace {

constexpr uint64_t kMaxCellsPerAxis = (uint64_t{1} << 21) - 3;  // keys stay below 2^63
// At most this many sampled splats set R and, when the whole box is too large for cells of
// 2 R, the box of the bulk of the splats.
constexpr std::size_t kSampleBits = 16;
// The bulk: the sampled coordinates between these quantiles, per axis.
constexpr double kBulkQuantile = 0.005;

// Every step-th element of v (at most about 2^kSampleBits of them), through `get`.
template <class T, class Get>
std::vector<double> sample(std::span<const T> v, Get&& get) {
  const std::size_t step = std::max<std::size_t>(1, v.size() >> kSampleBits);
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); i += step) out.push_back(get(v[i]));
  return out;
}

// The value at quantile q of `values` (reordered).
double quantile(std::vector<double>& values, double q) {
  const auto at = values.begin() + std::ptrdiff_t(double(values.size() - 1) * q);
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

// The splats' bounding box (lo, hi), from parallel chunks' boxes (min and max are exact: any
// order).
void bounding_box(std::span<const Vec3f> positions, double lo[3], double hi[3]) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = HUGE_VAL;
    hi[a] = -HUGE_VAL;
  }
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
      lo[a] = std::min(lo[a], b[a]);
      hi[a] = std::max(hi[a], b[a + 3]);
    }
}

// Cells larger than 2 R when the splats are sparse in them: a cell's candidates are gathered once
// for all its splats, so with a few splats per cell the gathering costs more than the tests. The
// cells grow (by at most kMaxCellGrowth) until a splat has about kTargetMates others in its cell.
// Only for the AVX-512 tests (16 candidates at a time), which are cheap beside the gathering; with
// AVX2 the instructions saved in gathering are spent in testing (callgrind, 1M splats: the same
// count). On 1M-splat clouds (CPU time of the graph, one thread, AVX-512): splat-synth's
// stratified CAD part, 6.3 mates in cells of 2 R, ~11 % faster with 12 to 30 mates; its i.i.d.
// sample, whose radii cover the larger gaps, 11.8 mates and no faster with more (slower from 15:
// its rows of ~37 are sorted apart from the tests, which then cost more than the gathering). Any
// side of at least 2 R gives the same graph.
constexpr double kTargetMates = 12;
constexpr double kMaxCellGrowth = 2;
// The mates are estimated from at most about 2^kMatesSampleBits splats (a few hundred pairs in
// one cell at 1M splats; sorted on one thread, so few).
constexpr std::size_t kMatesSampleBits = 13;

// The mean number of other splats in a splat's cell of side `cell` (cells from `lo`), estimated
// from the sampled positions `v` (a fraction m / n of the n splats): pairs of the sample in one
// cell, scaled by (n / m)^2.
double cell_mates(const std::vector<std::array<double, 3>>& v, std::size_t n, const double lo[3],
                  double cell) {
  std::vector<uint64_t> keys(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a)
      key = key << 21 | (uint64_t(std::floor((v[i][a] - lo[a]) / cell)) & ((1u << 21) - 1));
    keys[i] = key;
  }
  std::sort(keys.begin(), keys.end());
  double pairs = 0;
  for (std::size_t i = 0, j = 0; i < keys.size(); i = j) {
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    pairs += double(j - i) * double(j - i - 1) / 2;
  }
  const double m = double(v.size());
  return 2 * pairs / m * (double(n) / m);
}

// The factor (1 .. kMaxCellGrowth) by which cells of side `cell` grow: the mates grow as a
// power of the side (2 on surfaces), measured from the sample at 1 and 2 times the side.
double cell_growth(std::span<const Vec3f> positions, const double lo[3], double cell) {
  const std::size_t step = std::max<std::size_t>(1, positions.size() >> kMatesSampleBits);
  std::vector<std::array<double, 3>> v;
  for (std::size_t i = 0; i < positions.size(); i += step)
    v.push_back({positions[i].x, positions[i].y, positions[i].z});
  const double m1 = cell_mates(v, positions.size(), lo, cell);
  if (m1 >= kTargetMates) return 1;
  const double m2 = cell_mates(v, positions.size(), lo, kMaxCellGrowth * cell);
  if (!(m2 > m1)) return 1;
  if (m2 <= kTargetMates || m1 == 0) return kMaxCellGrowth;
  const double power = std::log(m2 / m1) / std::log(kMaxCellGrowth);
  return std::clamp(std::pow(kTargetMates / m1, 1 / power), 1.0, kMaxCellGrowth);
}

}  // namespace

// R: the 99.9th percentile of the radii. Spacing-based radii are alike, but the largest ones
// (splats at the rims of sampling cells) can be a third larger than the rest, and the cell size
// (2 R) sets how many candidates each splat tests: the largest 0.1 % are cheaper as big splats.
float small_radius(std::span<const float> radii) {
  // From a sample of at most 2^16 radii: R only sets the cell size (any R gives the same graph).
  const std::size_t step = std::max<std::size_t>(1, radii.size() >> kSampleBits);
  std::vector<float> copy;
  for (std::size_t i = 0; i < radii.size(); i += step) copy.push_back(radii[i]);
  auto q = copy.begin() + std::ptrdiff_t(copy.size() * 999 / 1000);
  std::nth_element(copy.begin(), q, copy.end());
  return *q;
}

// Cells of 2 R over the splats' bounding box, as long as an axis needs at most kMaxCellsPerAxis
// of them. On an axis that needs more, a few far-away splats (one stray point at 1e20 among
// millions at unit scale) would otherwise set the cell size and put the whole cloud into a
// handful of cells, each tested against all others; so such an axis covers the bulk (the
// sampled coordinates between the 0.5 % and 99.5 % quantiles) widened as far as the cells allow,
// and the splats beyond are clamped into its outer cells. Only when the bulk itself is wider
// than kMaxCellsPerAxis cells do the cells grow for that reason. Otherwise, with `grow`, they grow
// to hold about kTargetMates splats each (cell_growth).
Grid make_grid(std::span<const Vec3f> positions, float r_small, bool grow) {
  Grid g;
  double hi[3];
  bounding_box(positions, g.lo, hi);
  double cell = 2.0 * r_small * (1 + kCellMargin);
  bool bulk[3] = {false, false, false};
  double bulk_lo[3], bulk_hi[3];
  for (int a = 0; a < 3; ++a) {
    if ((hi[a] - g.lo[a]) / cell < double(kMaxCellsPerAxis)) continue;
    bulk[a] = true;
    std::vector<double> v = sample(positions, [a](const Vec3f& p) { return double(p[a]); });
    bulk_lo[a] = quantile(v, kBulkQuantile);
    bulk_hi[a] = quantile(v, 1 - kBulkQuantile);
    cell = std::max(cell, (bulk_hi[a] - bulk_lo[a]) / double(kMaxCellsPerAxis) * (1 + kCellMargin));
  }
  // (Larger cells still fit: every axis needed fewer than kMaxCellsPerAxis of the smaller ones.)
  if (grow && !bulk[0] && !bulk[1] && !bulk[2]) cell *= cell_growth(positions, g.lo, cell);
  for (int a = 0; a < 3; ++a) {
    if (!bulk[a]) continue;
    const double mid = 0.5 * (bulk_lo[a] + bulk_hi[a]),
                 half = 0.49 * double(kMaxCellsPerAxis) * cell;
    g.lo[a] = std::max(g.lo[a], mid - half);
    hi[a] = std::min(hi[a], mid + half);
  }
  g.inv_cell = 1 / cell;
  for (int a = 0; a < 3; ++a) g.cells[a] = uint64_t(std::floor((hi[a] - g.lo[a]) * g.inv_cell)) + 1;
  g.nx = g.cells[0] + 2;
  g.ny = g.cells[1] + 2;
  return g;
}

namespace {

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

}  // namespace

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
}  // namespace splatkit::graph::overlap
