#include "graph/segment_surfaces.h"

#include <numeric>
#include <stdexcept>

#include "graph/lowest_root_union_find.h"

namespace splatkit::graph {

Segmentation segment_surfaces(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                              uint8_t sharp_mask) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument("segment_surfaces: one edge flag per neighbour entry needed");
  const std::size_t n = graph.num_points();
  // Union-find over the continuous edges, rows in index order (the CSR arrays are read once,
  // front to back, which is what makes this faster than a breadth-first walk). The root of a
  // tree is always its lowest index, so the components and their ids are exactly those of a
  // breadth-first search started at the lowest unvisited index.
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
      const uint32_t j = graph.neighbors[k];
      if (j <= i || (edge_flags[k] & sharp_mask)) continue;
      unite(parent, static_cast<uint32_t>(i), j);
    }
  }
  Segmentation seg;
  seg.surface.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t root = find_root(parent, static_cast<uint32_t>(i));
    if (root == i) {
      seg.surface[i] = seg.count();
      seg.sizes.push_back(0);
    } else {
      seg.surface[i] = seg.surface[root];  // root < i: already labelled
    }
    ++seg.sizes[seg.surface[i]];
  }
  return seg;
}

}  // namespace splatkit::graph
