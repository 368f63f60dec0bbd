#include "graph/surface_borders.h"

#include <algorithm>

#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {

SurfaceBorders surface_borders(const NeighborGraph& graph, std::span<const uint32_t> label) {
  constexpr std::size_t kChunk = 4096;
  const std::size_t n = graph.num_points();
  std::vector<SurfaceBorders> parts(chunk_count(n, kChunk));
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    SurfaceBorders& out = parts[c];
    for (std::size_t i = begin; i < end; ++i) {
      const uint32_t a = label[i];
      bool border = false;
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        const uint32_t b = label[graph.neighbors[k]];
        if (a == b) continue;
        border = true;
        out.pairs.push_back(uint64_t{a} << 32 | b);
      }
      if (border) out.splats.push_back(uint32_t(i));
    }
    std::sort(out.pairs.begin(), out.pairs.end());
    out.pairs.erase(std::unique(out.pairs.begin(), out.pairs.end()), out.pairs.end());
  });
  SurfaceBorders all;
  for (const SurfaceBorders& p : parts) {
    all.splats.insert(all.splats.end(), p.splats.begin(), p.splats.end());
    all.pairs.insert(all.pairs.end(), p.pairs.begin(), p.pairs.end());
  }
  std::sort(all.pairs.begin(), all.pairs.end());
  all.pairs.erase(std::unique(all.pairs.begin(), all.pairs.end()), all.pairs.end());
  return all;
}

}  // namespace splatkit::graph
