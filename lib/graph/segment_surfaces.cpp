#include "graph/segment_surfaces.h"

#include <algorithm>
#include <stdexcept>

#include "graph/lowest_root_union_find.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kChunk = 16384;  // splats per task

}  // namespace

Segmentation segment_surfaces(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                              uint8_t sharp_mask) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument("segment_surfaces: one edge flag per neighbour entry needed");
  const std::size_t n = graph.num_points();
  // Union-find over the continuous edges (each once, from its lower end), in parallel chunks of
  // rows (unite_rows). The root of a tree is always its lowest index, so the components and their
  // ids are exactly those of a breadth-first search started at the lowest unvisited index.
  std::vector<uint32_t> parent(n);
  for_each_chunk(n, kChunk, [&](std::size_t, std::size_t i0, std::size_t i1) {
    for (std::size_t i = i0; i < i1; ++i) parent[i] = uint32_t(i);
  });
  unite_rows(parent, [&](std::size_t i, auto&& fn) {
    const auto row = graph.row(i);
    const uint8_t* flags = edge_flags.data() + graph.offsets[i];
    for (std::size_t k = 0; k < row.size(); ++k)
      if (row[k] > i && !(flags[k] & sharp_mask)) fn(row[k]);
  });
  // Ids in order of the roots: each chunk counts its roots, then numbers them after the earlier
  // chunks'; parent then maps a root to its id.
  Segmentation seg;
  seg.surface.resize(n);
  const std::size_t chunks = chunk_count(n, kChunk);
  std::vector<uint32_t> first_id(chunks + 1, 0);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t i0, std::size_t i1) {
    uint32_t roots = 0;
    for (std::size_t i = i0; i < i1; ++i) {
      seg.surface[i] = root_of(parent, uint32_t(i));
      roots += seg.surface[i] == i;
    }
    first_id[c + 1] = roots;
  });
  for (std::size_t c = 0; c < chunks; ++c) first_id[c + 1] += first_id[c];
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t i0, std::size_t i1) {
    uint32_t id = first_id[c];
    for (std::size_t i = i0; i < i1; ++i)
      if (seg.surface[i] == i) parent[i] = id++;
  });
  seg.sizes.assign(first_id[chunks], 0);
  for (std::size_t i = 0; i < n; ++i) {
    seg.surface[i] = parent[seg.surface[i]];
    ++seg.sizes[seg.surface[i]];
  }
  return seg;
}

}  // namespace splatkit::graph
