#include "graph/segment_surfaces.h"

#include <limits>
#include <stdexcept>

namespace splatkit::graph {

Segmentation segment_surfaces(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                              uint8_t sharp_mask) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument("segment_surfaces: one edge flag per neighbour entry needed");
  constexpr uint32_t kUnvisited = std::numeric_limits<uint32_t>::max();
  const std::size_t n = graph.num_points();
  Segmentation seg;
  seg.surface.assign(n, kUnvisited);
  std::vector<uint32_t> queue;
  queue.reserve(1024);
  for (std::size_t start = 0; start < n; ++start) {
    if (seg.surface[start] != kUnvisited) continue;
    const uint32_t id = seg.count();
    queue.clear();
    queue.push_back(static_cast<uint32_t>(start));
    seg.surface[start] = id;
    // The queue is consumed by index: it never shrinks, and its length is the region's size.
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const uint32_t i = queue[head];
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        const uint32_t j = graph.neighbors[k];
        if ((edge_flags[k] & sharp_mask) || seg.surface[j] != kUnvisited) continue;
        seg.surface[j] = id;
        queue.push_back(j);
      }
    }
    seg.sizes.push_back(static_cast<uint32_t>(queue.size()));
  }
  return seg;
}

}  // namespace splatkit::graph
