#include "graph/sphere_overlap_graph.h"

#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "splatkit/error.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kCellBlock = 1024;  // cells per task and per output block
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
  std::vector<float> x, y, z, r;
  std::vector<uint32_t> id;          // original index
  std::vector<uint64_t> cell_key;    // one per non-empty cell, ascending
  std::vector<uint32_t> cell_start;  // first splat of each cell, plus the count at the end
  float small_radius = 0;            // R: radii above it are big
};

void check(std::span<const Vec3f> positions, std::span<const float> radii) {
  if (radii.size() != positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one radius per position");
  if (positions.size() > std::size_t{0xFFFFFFFEu})
    throw std::invalid_argument("sphere_overlap_graph: more than 2^32 - 2 splats");
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
      throw std::invalid_argument("sphere_overlap_graph: radii must be finite and >= 0");
    const Vec3f& p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(ErrorKind::kBadInput,
                  "splat " + std::to_string(i) + " has a non-finite coordinate");
  }
}

// R: the 99.9th percentile of the radii. Spacing-based radii are alike, but the largest ones
// (splats at the rims of sampling cells) can be a third larger than the rest, and the cell size
// (2 R) sets how many candidates each splat tests: the largest 0.1 % are cheaper as big splats.
float small_radius(std::span<const float> radii) {
  std::vector<float> copy(radii.begin(), radii.end());
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
  for (const Vec3f& p : positions) {
    const double v[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
      g.lo[a] = std::min(g.lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
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

Sorted sort_by_cell(std::span<const Vec3f> positions, std::span<const float> radii, const Grid& g,
                    float r_small) {
  const std::size_t n = positions.size();
  std::vector<uint64_t> keys(n);
  std::vector<uint32_t> ids(n);
  tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
    for (std::size_t i = b; i < std::min(n, b + 65536); ++i) {
      keys[i] = g.key_of(positions[i]);
      ids[i] = uint32_t(i);
    }
  });
  radix_sort(keys, ids, g.key(g.cells[0] + 1, g.cells[1] + 1, g.cells[2] + 1));
  Sorted s;
  s.small_radius = r_small;
  s.x.resize(n);
  s.y.resize(n);
  s.z.resize(n);
  s.r.resize(n);
  s.id = std::move(ids);
  tbb::parallel_for(std::size_t{0}, n, std::size_t{65536}, [&](std::size_t b) {
    for (std::size_t k = b; k < std::min(n, b + 65536); ++k) {
      const Vec3f& p = positions[s.id[k]];
      s.x[k] = p.x;
      s.y[k] = p.y;
      s.z[k] = p.z;
      s.r[k] = radii[s.id[k]];
    }
  });
  for (std::size_t k = 0; k < n; ++k)
    if (k == 0 || keys[k] != keys[k - 1]) {
      s.cell_key.push_back(keys[k]);
      s.cell_start.push_back(uint32_t(k));
    }
  s.cell_start.push_back(uint32_t(n));
  return s;
}

// Rows of the splats of a run of cells, in sorted order: their small neighbours.
struct Block {
  std::vector<uint32_t> counts, neighbors;
};

// Candidates of one cell: up to 9 runs [begin, end) of sorted splats.
using Runs = std::array<std::pair<uint32_t, uint32_t>, 9>;

// Appends to row (from `count`) the splats of [a, b) that overlap splat p (sorted position) and
// are small; returns the new count. row must have room for b - a more entries. Branch-free: every
// candidate is written and kept by advancing the count (about a third of the candidates are
// neighbours, so a branch would mispredict often). With SSE2, four candidates per step; the
// arithmetic is the scalar expression's, lane by lane, so the answers are the same.
uint32_t overlaps_in_run(const Sorted& s, uint32_t p, uint32_t a, uint32_t b, uint32_t* row,
                         uint32_t count) {
  const float px = s.x[p], py = s.y[p], pz = s.z[p], pr = s.r[p], R = s.small_radius;
  uint32_t q = a;
#if defined(__SSE2__)
  const __m128 vx = _mm_set1_ps(px), vy = _mm_set1_ps(py), vz = _mm_set1_ps(pz),
               vr = _mm_set1_ps(pr), vR = _mm_set1_ps(R);
  for (; q + 4 <= b; q += 4) {
    const __m128 dx = _mm_sub_ps(vx, _mm_loadu_ps(&s.x[q]));
    const __m128 dy = _mm_sub_ps(vy, _mm_loadu_ps(&s.y[q]));
    const __m128 dz = _mm_sub_ps(vz, _mm_loadu_ps(&s.z[q]));
    const __m128 rq = _mm_loadu_ps(&s.r[q]);
    const __m128 sum = _mm_add_ps(vr, rq);
    const __m128 d2 =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    unsigned mask = unsigned(
        _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(d2, _mm_mul_ps(sum, sum)), _mm_cmple_ps(rq, vR))));
    if (p - q < 4) mask &= ~(1u << (p - q));
    for (int k = 0; k < 4; ++k) {
      row[count] = s.id[q + k];
      count += (mask >> k) & 1;
    }
  }
#endif
  for (; q < b; ++q) {
    const float dx = px - s.x[q], dy = py - s.y[q], dz = pz - s.z[q];
    const float sum = pr + s.r[q];
    row[count] = s.id[q];
    count += (dx * dx + dy * dy + dz * dz < sum * sum) & (q != p) & (s.r[q] <= R);
  }
  return count;
}

void small_rows_of_cell(const Sorted& s, std::size_t c, const Runs& runs,
                        std::vector<uint32_t>& row, Block& out) {
  std::size_t candidates = 0;
  for (const auto& [a, b] : runs) candidates += b - a;
  if (row.size() < candidates) row.resize(candidates);
  for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
    uint32_t count = 0;
    if (s.r[p] <= s.small_radius) {
      for (const auto& [a, b] : runs) count = overlaps_in_run(s, p, a, b, row.data(), count);
      std::sort(row.begin(), row.begin() + count);
    }
    out.counts.push_back(count);
    out.neighbors.insert(out.neighbors.end(), row.begin(), row.begin() + count);
  }
}

// Cells [c0, c1): the 27 surrounding cells are 9 runs of 3 consecutive keys, each at a fixed
// key offset from the cell's own key, so one forward-only cursor per run finds them.
void small_rows(const Sorted& s, const Grid& g, std::size_t c0, std::size_t c1, Block& out) {
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
  std::vector<uint32_t> row;
  for (std::size_t c = c0; c < c1; ++c) {
    for (int k = 0; k < 9; ++k) {
      const uint64_t lo = uint64_t(int64_t(keys[c]) + offset[k]), hi = lo + 2;
      std::size_t& cur = cursor[k];
      while (cur < cells && keys[cur] < lo) ++cur;
      std::size_t end = cur;
      while (end < cells && keys[end] <= hi) ++end;
      runs[k] = {s.cell_start[cur], s.cell_start[end]};
    }
    small_rows_of_cell(s, c, runs, row, out);
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
  const std::size_t n = s.id.size();
  std::vector<uint32_t> bigs;
  for (uint32_t p = 0; p < n; ++p)
    if (s.r[p] > s.small_radius) bigs.push_back(p);
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

// Writes row `id`: its small neighbours `base` merged with its entries in `pairs`.
void write_row(uint32_t id, std::span<const uint32_t> base, std::size_t extra,
               const std::vector<uint64_t>& pairs, uint32_t* out) {
  if (extra == 0) {
    std::copy(base.begin(), base.end(), out);
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

NeighborGraph assemble(const Sorted& s, std::vector<Block>& blocks,
                       const std::vector<uint64_t>& pairs) {
  const std::size_t n = s.id.size();
  NeighborGraph graph;
  graph.offsets.assign(n + 1, 0);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const uint32_t first = s.cell_start[b * kCellBlock];
    for (std::size_t k = 0; k < blocks[b].counts.size(); ++k)
      graph.offsets[std::size_t{s.id[first + k]} + 1] = blocks[b].counts[k];
  }
  for (uint64_t pair : pairs) ++graph.offsets[(pair >> 32) + 1];
  for (std::size_t i = 0; i < n; ++i) graph.offsets[i + 1] += graph.offsets[i];
  graph.neighbors.resize(graph.offsets[n]);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    const uint32_t first = s.cell_start[b * kCellBlock];
    const uint32_t* base = blocks[b].neighbors.data();
    for (std::size_t k = 0; k < blocks[b].counts.size(); ++k) {
      const uint32_t id = s.id[first + k], count = blocks[b].counts[k];
      const uint64_t at = graph.offsets[id];
      write_row(id, {base, count}, graph.offsets[std::size_t{id} + 1] - at - count, pairs,
                graph.neighbors.data() + at);
      base += count;
    }
    Block().counts.swap(blocks[b].counts);
    Block().neighbors.swap(blocks[b].neighbors);
  });
  return graph;
}

}  // namespace

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii) {
  check(positions, radii);
  const std::size_t n = positions.size();
  if (n == 0) return NeighborGraph{{0}, {}};
  const float r_small = small_radius(radii);
  if (!(r_small > 0)) {
    // All radii 0: (0 + 0)² is never > d². Otherwise almost all are 0 and a grid has no scale.
    if (*std::max_element(radii.begin(), radii.end()) == 0)
      return NeighborGraph{std::vector<uint64_t>(n + 1, 0), {}};
    return SpatialIndex(positions).sphere_overlaps(radii);
  }
  const Grid g = make_grid(positions, r_small);
  const Sorted s = sort_by_cell(positions, radii, g, r_small);
  std::vector<uint64_t> pairs;
  if (!big_pairs(s, g, pairs)) return SpatialIndex(positions).sphere_overlaps(radii);
  const std::size_t cells = s.cell_key.size();
  std::vector<Block> blocks((cells + kCellBlock - 1) / kCellBlock);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    small_rows(s, g, b * kCellBlock, std::min(cells, (b + 1) * kCellBlock), blocks[b]);
  });
  return assemble(s, blocks, pairs);
}

}  // namespace splatkit::graph
