#include "graph/merge_small_surfaces.h"

#include <algorithm>
#include <cmath>
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

Segmentation merge_small_surfaces(const NeighborGraph& graph, Segmentation seg, uint32_t min_size,
                                  SplatSpheres splats) {
  const std::size_t n = graph.num_points();
  if (seg.surface.size() != n)
    throw std::invalid_argument("merge_small_surfaces: one surface id per splat needed");
  const bool spheres = !splats.positions.empty();
  if (spheres && (splats.positions.size() != n || splats.radii.size() != n))
    throw std::invalid_argument("merge_small_surfaces: one position and radius per splat needed");
  const uint32_t count = seg.count();
  std::vector<uint32_t> parent(count), size = seg.sizes;  // union-find over surfaces
  for (uint32_t s = 0; s < count; ++s) parent[s] = s;
  const SurfaceMembers groups = surface_members(seg.surface, count);
  // parts[g]: the original surfaces in group g (g a root).
  std::vector<std::vector<uint32_t>> parts(count);
  for (uint32_t s = 0; s < count; ++s) parts[s] = {s};
  // Groups a and b become one, under the lower id.
  auto join = [&](uint32_t a, uint32_t b) {
    const uint32_t keep = std::min(a, b), gone = std::max(a, b);
    parent[gone] = keep;
    size[keep] += size[gone];
    size[gone] = 0;
    if (parts[keep].size() < parts[gone].size()) parts[keep].swap(parts[gone]);
    parts[keep].insert(parts[keep].end(), parts[gone].begin(), parts[gone].end());
    parts[gone] = {};
  };
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
      join(best, f);
      merged = true;
    }
  }
  // Isolated fragments left: each joins the group of the nearest splat outside it when that one
  // nearly touches one of its splats (nearest first over the fragment's splats, then the lower
  // index). The index is built only when there is such a fragment.
  std::vector<uint32_t> isolated;
  if (spheres && min_size > 1)
    for (uint32_t s = 0; s < count; ++s)
      if (parent[s] == s && size[s] < min_size) isolated.push_back(s);
  if (!isolated.empty()) {
    const SpatialIndex index(splats.positions);
    std::vector<uint32_t> near;
    std::vector<float> d2;
    for (const uint32_t f : isolated) {
      const std::size_t k = std::min<std::size_t>(n, size[f] + 1);
      near.resize(k);
      d2.resize(k);
      float best_d2 = INFINITY;
      uint32_t best = f;
      for (uint32_t s : parts[f])
        for (uint32_t i : groups.of(s)) {
          const std::size_t found = index.knn(splats.positions[i], k, near.data(), d2.data());
          for (std::size_t q = 0; q < found; ++q) {
            const uint32_t j = near[q];
            const uint32_t t = root(parent, seg.surface[j]);
            if (t == f) continue;
            const float reach = 2 * (splats.radii[i] + splats.radii[j]);
            if (d2[q] < reach * reach && d2[q] < best_d2) best_d2 = d2[q], best = t;
            break;  // the nearest splat outside the fragment
          }
        }
      if (best == f) continue;
      join(best, f);
    }
  }
  std::vector<uint32_t> label(n);
  for (std::size_t i = 0; i < n; ++i) label[i] = root(parent, seg.surface[i]);
  return renumber_surfaces(label, count);
}

}  // namespace splatkit::graph
