// The uniform grid of sphere_overlap_graph: the splats sorted by cell into their own arrays
// (structure of arrays), and the walk over each cell's 27 surrounding cells.
//
// Cells have side 2 R (R the largest "small" radius, a little more for float rounding) or more, so
// two small splats that overlap lie in the same or adjacent cells. Cell coordinates are clamped to
// the grid's box, which never moves two splats further apart in cells: a box that leaves out a
// few far-away splats (see make_grid) gives the same graph.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "splatkit/vec3.h"

namespace splatkit::graph::overlap {

constexpr std::size_t kPad = 16;         // spare entries after the sorted arrays, for 16-wide loads
constexpr std::size_t kChunk = 1 << 16;  // splats per task of the simple parallel loops
// Cells are this much larger than 2 R, so float rounding of the cell coordinates or of the
// distance test can never put two overlapping small splats two cells apart.
constexpr double kCellMargin = 1e-5;

struct Grid {
  double lo[3];
  double inv_cell;
  uint64_t cells[3];  // cells per axis, without the padding layer on each side
  uint64_t nx, ny;    // padded sizes of x and y, for keys

  // Padded cell coordinate (1 .. cells[a]) of a coordinate along axis a, clamped (in double
  // first: a far coordinate's cell number need not fit in 64 bits).
  uint64_t coord(int a, double v) const {
    const double c = std::floor((v - lo[a]) * inv_cell);
    if (!(c >= 0)) return 1;
    if (c >= double(cells[a] - 1)) return cells[a];
    return uint64_t(c) + 1;
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

// Candidates of one cell: up to 9 runs [begin, end) of sorted splats.
using Runs = std::array<std::pair<uint32_t, uint32_t>, 9>;

// R: the 99.9th percentile of the radii (from a sample).
float small_radius(std::span<const float> radii);

// The grid for splats at `positions` with small radius r_small > 0: cells of side 2 R, or up to
// twice that with `grow` when a sample shows few splats per cell (see make_grid).
Grid make_grid(std::span<const Vec3f> positions, float r_small, bool grow = false);

// The splats sorted by cell (stable: by index within a cell), with their radii and, when
// `normals` is not empty, their normals.
Sorted sort_by_cell(std::span<const Vec3f> positions, std::span<const float> radii,
                    std::span<const Vec3f> normals, const Grid& g, float r_small);

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

}  // namespace splatkit::graph::overlap
