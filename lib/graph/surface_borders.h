// surface_borders: where the surfaces of a segmentation meet — the splats with a neighbour on
// another surface, and the pairs of surfaces joined by an edge. One pass over the rows, in
// parallel chunks joined in order (the same result for any thread count).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/spatial_index.h"

namespace splatkit::graph {

struct SurfaceBorders {
  std::vector<uint32_t> splats;  // splats with a neighbour of another label, ascending
  std::vector<uint64_t> pairs;   // (a << 32 | b) for every edge between labels a != b, ascending,
                                 // each pair once (both (a, b) and (b, a) are there)
};

// graph: symmetric neighbour rows; label: #N (any values). O(E).
SurfaceBorders surface_borders(const NeighborGraph& graph, std::span<const uint32_t> label);

// The same from the rows of `candidates` only (ascending indices that include every border
// splat, e.g. the old border splats and every splat that changed or has a neighbour that did):
// O(their rows).
SurfaceBorders surface_borders(const NeighborGraph& graph, std::span<const uint32_t> label,
                               std::span<const uint32_t> candidates);

}  // namespace splatkit::graph
