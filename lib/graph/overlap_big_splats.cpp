#include "graph/overlap_big_splats.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/for_each_chunk.h"
#include "splatkit/spatial_index.h"

namespace splatkit::graph::overlap {
namespace {

constexpr double kMaxBigRowsPerSplat = 8;  // budget of the big splats' cell-row scans

// Neighbours of big splat b (sorted position): small splats in the cells within r_b + R, and
// the big splats bigs[k] for k in `big_neighbors`. Original indices, ascending.
std::vector<uint32_t> big_row(const Sorted& s, const Grid& g, uint32_t b,
                              const std::vector<uint32_t>& bigs,
                              std::span<const uint32_t> big_neighbors) {
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
  for (uint32_t k : big_neighbors) row.push_back(s.id[bigs[k]]);
  std::sort(row.begin(), row.end());
  return row;
}

}  // namespace

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
  double rows = 0;
  for (uint32_t b : bigs) {
    const double cells = 2 * (double(s.r[b]) + s.small_radius) * g.inv_cell + 3;
    rows += cells * cells;
  }
  if (rows > kMaxBigRowsPerSplat * double(n)) return false;
  // The big splats among themselves: a kd-tree over them alone, with the same test as every
  // other pair (testing each against all the others cost B^2: 0.1 % of 64M splats is 64 000).
  std::vector<Vec3f> centres(bigs.size());
  std::vector<float> radii(bigs.size());
  for (std::size_t k = 0; k < bigs.size(); ++k) {
    centres[k] = {s.x[bigs[k]], s.y[bigs[k]], s.z[bigs[k]]};
    radii[k] = s.r[bigs[k]];
  }
  const NeighborGraph among = SpatialIndex(centres).sphere_overlaps(radii);
  std::vector<std::vector<uint32_t>> found(bigs.size());
  tbb::parallel_for(std::size_t{0}, bigs.size(),
                    [&](std::size_t k) { found[k] = big_row(s, g, bigs[k], bigs, among.row(k)); });
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

}  // namespace splatkit::graph::overlap
