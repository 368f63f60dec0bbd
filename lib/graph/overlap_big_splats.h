// The big splats of sphere_overlap_graph (radius above R, about 0.1 %): each finds its small
// neighbours by scanning the grid cells within r_b + R of its centre, and its big ones in a
// kd-tree over the big splats alone; the small splats it overlaps get it in their rows.
#pragma once

#include <cstdint>
#include <vector>

#include "graph/overlap_grid.h"

namespace splatkit::graph::overlap {

// The extra entries the big splats bring: (row << 32 | neighbour) in original indices, sorted,
// appended to `pairs`. False when they would cost too much (cell scans adding up to more than 8
// cells per splat): then the caller uses the kd-tree.
bool big_pairs(const Sorted& s, const Grid& g, std::vector<uint64_t>& pairs);

}  // namespace splatkit::graph::overlap
