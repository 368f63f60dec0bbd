// sphere_overlap_graph: the neighbour graph of seed [3.1], E = {(i, j) : |C_i − C_j| < r_i + r_j},
// with a uniform grid instead of a kd-tree — the first phase of build_splat_graph.
//
// Same answer as SpatialIndex::sphere_overlaps, entry for entry: j is a neighbour of i (j != i)
// iff squared_distance(C_i, C_j) < (r_i + r_j)², both computed in float the same way; rows
// ascending. Built for splat clouds, where radii come from the local spacing and are alike:
//   - cells of side 2 R, R the largest "small" radius, so two small splats that overlap lie in
//     the same or adjacent cells (27 cells, walked as 9 runs of 3 cells that are consecutive in
//     the cells' key order; one cursor per run moves forward only, so no hashing, no search);
//   - splats are sorted by cell (parallel LSD radix sort on the cell key) into their own arrays;
//   - the 27 cells' small splats that can reach a cell's bounding box are copied together once
//     per cell and tested against each of its splats (eight at a time with AVX2, chosen at run
//     time; rows up to 64 sorted by ranking, without branches);
//   - two passes over the cells: the row lengths, then each row again, written in place — no
//     copy of the rows in cell order;
//   - R is the 99.9th percentile of the radii; the "big" splats above it (at most 0.1 %) find
//     their neighbours by scanning the cells within r_b + R of their centre and by testing each
//     other directly, and are added to the rows of the small splats they overlap.
// When the big splats would cost too much (more than 8192 of them, or their cell scans add up to
// more than 8 cells per splat) it falls back to SpatialIndex::sphere_overlaps.
//
// positions, radii: #N each. Throws std::invalid_argument for different sizes or a radius that
// is negative or not finite, and Error(kBadInput) naming the first splat with a non-finite
// coordinate (like SpatialIndex). Runs in parallel
// with TBB; the result does not depend on the thread count. Memory: the result (8 bytes/splat +
// 4 per row entry) plus about 50 bytes/splat transiently.
#pragma once

#include <span>

#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii);

// The same graph with the vector code limited to `limit` (lowered further to what the CPU runs),
// so that tests can compare every path: portable scalar code; AVX2 (tests and ranking sort);
// AVX-512 (bitonic sort of rows up to 16).
enum class OverlapSimd { kPortable, kAvx2, kAvx512 };
NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   OverlapSimd limit);

}  // namespace splatkit::graph
