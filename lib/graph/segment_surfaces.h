// Segmentation into smooth surfaces: breadth-first search over continuous edges ([IvoMSc] §5.4,
// fig. 5.4; docs/references.md).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/spatial_index.h"

namespace splatkit::graph {

// The surface id of splats that belong to no kept surface (segment-surfaces --min-size; SURF).
inline constexpr uint32_t kNoSurface = 0xFFFFFFFFu;

struct Segmentation {
  std::vector<uint32_t> surface;  // #N: surface id of every splat, 0 .. count - 1
  std::vector<uint32_t> sizes;    // #count: splats per surface
  uint32_t count() const { return static_cast<uint32_t>(sizes.size()); }
};

// graph: symmetric neighbour rows (NeighborGraph layout). edge_flags: one byte per entry of
// graph.neighbors; an entry with (flags & sharp_mask) != 0 is a sharp edge and is not followed.
// The flags must be symmetric (entry i->j sharp iff j->i sharp; build_splat_graph's are), else
// the regions depend on the search order. Regions are the connected components of the continuous
// edges; ids are given in the order of each region's lowest splat index (a new region starts at
// the lowest unvisited index), so they are stable and independent of thread count. A splat with
// no continuous edge is a surface of its own. Throws std::invalid_argument when edge_flags does
// not match graph.neighbors in size. Computed with a union-find (lowest index as root), which
// gives the same components and ids as the breadth-first search; O(E α(N)), in parallel.
Segmentation segment_surfaces(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                              uint8_t sharp_mask);

}  // namespace splatkit::graph
