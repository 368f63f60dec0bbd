// sphere_overlap_graph: the neighbour graph of bounding spheres that strictly overlap,
// E = {(i, j) : |C_i − C_j| < r_i + r_j}, with a uniform grid instead of a kd-tree — the first
// phase of build_splat_graph.
//
// Same answer as SpatialIndex::sphere_overlaps, entry for entry: j is a neighbour of i (j != i)
// iff squared_distance(C_i, C_j) < (r_i + r_j)², both computed in float the same way; rows
// ascending. Built for splat clouds, where radii come from the local spacing and are alike:
//   - cells of side 2 R, R the largest "small" radius, so two small splats that overlap lie in
//     the same or adjacent cells; with AVX-512, up to twice that side where a sample shows few
//     splats per cell, so that each cell's candidates serve more splats (graph/overlap_grid.h) (27 cells, walked as 9 runs of 3 cells that are consecutive in
//     the cells' key order; one cursor per run moves forward only, so no hashing, no search);
//   - splats are sorted by cell (parallel LSD radix sort on the cell key) into their own arrays;
//   - the 27 cells' small splats that can reach a cell's bounding box are copied together once
//     per cell and tested against each of its splats (graph/overlap_candidates.h: 16 at a time
//     with AVX-512, 8 with AVX2, one by one in the portable code; see splatkit/simd_level.h);
//     a row of up to 16 is gathered and sorted in one AVX-512 register; a longer one is tested
//     again eight at a time, and rows up to 64 are sorted by ranking without branches, longer
//     ones by std::sort;
//   - two passes over the cells: the row lengths, then each row again, written in place — no
//     copy of the rows in cell order (fewer fresh pages, which cost more than the second pass);
//   - R is the 99.9th percentile of the radii; the "big" splats above it (about 0.1 %) find
//     their small neighbours by scanning the cells within r_b + R of their centre and each other
//     in a kd-tree over the big splats alone, and are added to the rows of the small splats they
//     overlap.
// A few splats far from the rest do not set the cell size: an axis that would need more than
// 2^21 cells covers the bulk of the splats, and the far ones are clamped into its outer cells
// (graph/overlap_grid.h). When the cells are crowded (more than 1024 cell-mates per splat on
// average: far clusters, or a bulk wider than 2^21 cells) or the big splats' cell scans would add
// up to more than 8 cells per splat, it falls back to SpatialIndex::sphere_overlaps, which
// refuses (Error(kBadInput)) a graph of more than 1024 neighbours per splat on average: radii far
// larger than the spacing (a radius column in other units, or scaled) would fill the memory.
//
// positions, radii: #N each. Throws std::invalid_argument for different sizes or a radius that
// is negative or not finite, and Error(kBadInput) naming the first splat with a non-finite
// coordinate (like SpatialIndex). Runs in parallel with TBB; the result does not depend on the
// thread count. Memory: the result (8 bytes/splat + 4 per row entry; with sharp edges 1 more per
// entry, made at the end from one bit per entry) plus about 40 bytes/splat transiently (52 with
// sharp edges; 28 of them are lent back with LentSplats).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/simd_level.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// The vector code used is min(limit, simd_level()), so that tests can compare every path:
// portable scalar code (also at kSse2); AVX2 (tests and ranking sort); AVX-512 (16-wide tests and
// copies, rows up to 16 compressed and sorted in one register). OverlapSimd is the older name.
using OverlapSimd = SimdLevel;

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   SimdLevel limit = SimdLevel::kAvx512);

// Which edges are sharp: n_i·n_j (Vec3f's dot) not >= threshold, so that a NaN normal
// makes its edges sharp.
struct SharpEdges {
  std::span<const Vec3f> normals;  // #N
  float threshold = 0.9f;
  uint8_t flag = 1;  // the value set in the flags
};

struct SharpEdgeMarks {
  std::vector<uint8_t> flags;  // #entries, parallel to neighbors: sharp.flag or 0
  std::vector<uint32_t> rows;  // the rows with a sharp edge, ascending
};

// The same graph, and its sharp edges. The normals are sorted with the splats and copied with
// the candidates, so the test runs where the rows are found, on data in cache; the graphs the
// grid leaves to the kd-tree are marked row by row afterwards. Throws std::invalid_argument when
// the normals are not #N.
NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   const SharpEdges& sharp, SharpEdgeMarks& marks,
                                   SimdLevel limit = SimdLevel::kAvx512);

// The splats' arrays lent to the graph: while the grid's rows are written only its sorted copy
// of them is held, and they are filled again from it (the same values, in new buffers: spans
// taken before the call are no longer valid) before the call returns or throws. That keeps 28
// bytes per splat off the peak of memory.
struct LentSplats {
  std::vector<Vec3f>& positions;
  std::vector<float>& radii;
  std::vector<Vec3f>& normals;
};

// The graph and its sharp edges (n_i·n_j not >= sharp_threshold, marked `flag`) as above, of
// lent arrays.
NeighborGraph sphere_overlap_graph(LentSplats splats, float sharp_threshold, uint8_t flag,
                                   SharpEdgeMarks& marks, SimdLevel limit = SimdLevel::kAvx512);

}  // namespace splatkit::graph
