#include "graph/surface_borders.h"

#include <algorithm>

#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {
namespace {

// splat(k) for k in [0, count): the rows to read.
template <class Splat>
SurfaceBorders borders_of(const NeighborGraph& graph, std::span<const uint32_t> label,
                          std::size_t count, Splat&& splat) {
  constexpr std::size_t kChunk = 4096;
  std::vector<SurfaceBorders> parts(chunk_count(count, kChunk));
  for_each_chunk(count, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    SurfaceBorders& out = parts[c];
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t i = splat(k), a = label[i];
      bool border = false;
      for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
        const uint32_t b = label[graph.neighbors[e]];
        if (a == b) continue;
        border = true;
        out.pairs.push_back(uint64_t{a} << 32 | b);
      }
      if (border) out.splats.push_back(i);
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

}  // namespace

SurfaceBorders surface_borders(const NeighborGraph& graph, std::span<const uint32_t> label) {
  return borders_of(graph, label, graph.num_points(), [](std::size_t k) { return uint32_t(k); });
}

SurfaceBorders surface_borders(const NeighborGraph& graph, std::span<const uint32_t> label,
                               std::span<const uint32_t> candidates) {
  return borders_of(graph, label, candidates.size(), [&](std::size_t k) { return candidates[k]; });
}

}  // namespace splatkit::graph
