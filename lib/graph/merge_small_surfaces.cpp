#include "graph/merge_small_surfaces.h"

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "graph/renumber_surfaces.h"
#include "graph/surface_members.h"

namespace splatkit::graph {
namespace {

uint32_t root(std::vector<uint32_t>& parent, uint32_t s) {
  while (parent[s] != s) s = parent[s] = parent[parent[s]];
  return s;
}

}  // namespace

Segmentation merge_small_surfaces(const NeighborGraph& graph, Segmentation seg, uint32_t min_size) {
  const std::size_t n = graph.num_points();
  if (seg.surface.size() != n)
    throw std::invalid_argument("merge_small_surfaces: one surface id per splat needed");
  const uint32_t count = seg.count();
  std::vector<uint32_t> parent(count), size = seg.sizes;  // union-find over surfaces
  for (uint32_t s = 0; s < count; ++s) parent[s] = s;
  const SurfaceMembers groups = surface_members(seg.surface, count);
  // parts[g]: the original surfaces in group g (g a root).
  std::vector<std::vector<uint32_t>> parts(count);
  for (uint32_t s = 0; s < count; ++s) parts[s] = {s};
  std::vector<uint32_t> fragments;
  std::vector<uint32_t> touched;  // the neighbour group of every edge leaving one fragment
  for (bool merged = min_size > 1; merged;) {
    merged = false;
    fragments.clear();
    for (uint32_t s = 0; s < count; ++s)
      if (parent[s] == s && size[s] < min_size) fragments.push_back(s);
    std::sort(fragments.begin(), fragments.end(), [&](uint32_t a, uint32_t b) {
      return size[a] != size[b] ? size[a] < size[b] : a < b;
    });
    for (uint32_t f : fragments) {
      if (parent[f] != f || size[f] >= min_size) continue;  // joined earlier in this pass
      touched.clear();
      for (uint32_t s : parts[f])
        for (uint32_t i : groups.of(s)) {
          for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
            const uint32_t t = root(parent, seg.surface[graph.neighbors[e]]);
            if (t != f) touched.push_back(t);
          }
        }
      if (touched.empty()) continue;
      std::sort(touched.begin(), touched.end());
      uint32_t best = touched[0], best_edges = 0;
      for (std::size_t a = 0; a < touched.size();) {
        std::size_t b = a;
        while (b < touched.size() && touched[b] == touched[a]) ++b;
        const uint32_t t = touched[a], edges = uint32_t(b - a);
        if (edges > best_edges || (edges == best_edges && size[t] > size[best]))
          best = t, best_edges = edges;
        a = b;
      }
      const uint32_t keep = std::min(best, f), gone = std::max(best, f);
      parent[gone] = keep;
      size[keep] += size[gone];
      size[gone] = 0;
      if (parts[keep].size() < parts[gone].size()) parts[keep].swap(parts[gone]);
      parts[keep].insert(parts[keep].end(), parts[gone].begin(), parts[gone].end());
      parts[gone] = {};
      merged = true;
    }
  }
  std::vector<uint32_t> label(n);
  for (std::size_t i = 0; i < n; ++i) label[i] = root(parent, seg.surface[i]);
  return renumber_surfaces(label, count);
}

}  // namespace splatkit::graph
