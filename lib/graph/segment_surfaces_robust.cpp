#include "graph/segment_surfaces_robust.h"

#include "graph/estimate_normal_noise.h"
#include "graph/lowest_root_union_find.h"
#include "graph/renumber_surfaces.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace splatkit::graph {
namespace {

constexpr uint32_t kUnset = 0xFFFFFFFFu;

struct Rows {
  const NeighborGraph& graph;
  std::span<const uint8_t> flags;
  uint8_t sharp;
  // fn(j) for every continuous neighbour j of i.
  template <class Fn>
  void continuous(std::size_t i, Fn&& fn) const {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k)
      if (!(flags[k] & sharp)) fn(graph.neighbors[k]);
  }
};

std::vector<uint8_t> find_cores(const Rows& rows, std::span<const Vec3f> normals, float w_c) {
  std::vector<uint8_t> core(normals.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, normals.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        bool ok = std::isfinite(normals[i].x + normals[i].y + normals[i].z);
                        rows.continuous(
                            i, [&](uint32_t j) { ok = ok && dot(normals[i], normals[j]) >= w_c; });
                        core[i] = ok;
                      }
                    });
  return core;
}

// label[i] = the root (lowest index) of i's core component, for cores in components of at least
// min_size splats; kUnset for every other splat. parent, size: scratch of N entries.
void core_components(const Rows& rows, const std::vector<uint8_t>& core, uint32_t min_size,
                     std::vector<uint32_t>& parent, std::vector<uint32_t>& size,
                     std::vector<uint32_t>& label) {
  const std::size_t n = core.size();
  std::iota(parent.begin(), parent.end(), 0u);
  unite_rows(parent, [&](std::size_t i, auto&& fn) {
    if (core[i])
      rows.continuous(i, [&](uint32_t j) {
        if (j > i && core[j]) fn(j);
      });
  });
  std::fill(size.begin(), size.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    label[i] = core[i] ? find_root(parent, uint32_t(i)) : kUnset;
    if (core[i]) ++size[label[i]];
  }
  for (std::size_t i = 0; i < n; ++i)
    if (core[i] && size[label[i]] < min_size) label[i] = kUnset;
}

// Breadth-first from every labelled splat at once over continuous edges, one hop per round:
// in a round, the splats labelled in the previous one hand their label to their unlabelled
// continuous neighbours in ascending index order (so the lowest-indexed giver wins a tie), and
// walking them in index order reads the rows front to back. The first round starts from the
// labelled splats next to an unlabelled one, marked from the unlabelled side (the smaller one).
void grow(const Rows& rows, std::vector<uint32_t>& label) {
  std::vector<uint8_t> front(label.size(), 0);
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (label[i] != kUnset) continue;
    rows.continuous(i, [&](uint32_t j) { front[j] = label[j] != kUnset; });
  }
  std::vector<uint32_t> round, next;
  for (std::size_t i = 0; i < label.size(); ++i)
    if (front[i]) round.push_back(uint32_t(i));
  while (!round.empty()) {
    next.clear();
    for (uint32_t i : round)
      rows.continuous(i, [&](uint32_t j) {
        if (label[j] != kUnset) return;
        label[j] = label[i];
        next.push_back(j);
      });
    std::sort(next.begin(), next.end());
    round.swap(next);
  }
}

// Components of the continuous edges among the splats no core reached. parent: scratch.
void label_the_rest(const Rows& rows, std::vector<uint32_t>& label, std::vector<uint32_t>& parent) {
  const std::size_t n = label.size();
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    parent[i] = uint32_t(i);
    any = any || label[i] == kUnset;
  }
  if (!any) return;
  unite_rows(parent, [&](std::size_t i, auto&& fn) {
    if (label[i] == kUnset)
      rows.continuous(i, [&](uint32_t j) {
        if (j > i && label[j] == kUnset) fn(j);
      });
  });
  for (std::size_t i = 0; i < n; ++i)
    if (label[i] == kUnset) label[i] = find_root(parent, uint32_t(i));
}

// The share of the sharp edges (each counted once) whose two splats lie in one surface of
// `segmentation`; 0 when there is no sharp edge.
double share_of_sharp_edges_within(const Rows& rows, const Segmentation& segmentation) {
  const NeighborGraph& g = rows.graph;
  uint64_t sharp = 0, within = 0;
  for (std::size_t i = 0; i < g.num_points(); ++i)
    for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k) {
      const uint32_t j = g.neighbors[k];
      if (!(rows.flags[k] & rows.sharp) || j <= i) continue;
      ++sharp;
      within += segmentation.surface[i] == segmentation.surface[j];
    }
  return sharp ? double(within) / double(sharp) : 0.0;
}

}  // namespace

float default_core_threshold(float sharp_threshold) {
  return float(std::sqrt((1.0 + double(std::clamp(sharp_threshold, -1.0f, 1.0f))) / 2));
}

Segmentation segment_surfaces_robust(const NeighborGraph& graph,
                                     std::span<const uint8_t> edge_flags, uint8_t sharp_mask,
                                     std::span<const Vec3f> positions,
                                     std::span<const Vec3f> normals,
                                     const RobustSegmentOptions& options, RobustSegmentInfo* info) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument(
        "segment_surfaces_robust: one edge flag per neighbour entry needed");
  if (normals.size() != graph.num_points() || positions.size() != graph.num_points())
    throw std::invalid_argument("segment_surfaces_robust: one position and normal per splat");
  if (options.min_core_size == 0)
    throw std::invalid_argument("segment_surfaces_robust: min_core_size must be >= 1");
  const Rows rows{graph, edge_flags, sharp_mask};
  RobustSegmentInfo chosen;
  if (options.core_threshold) {
    chosen.core_threshold = *options.core_threshold;
  } else {
    chosen.normal_noise_degrees =
        estimate_normal_noise(graph, edge_flags, sharp_mask, positions, normals);
    chosen.core_threshold = default_core_threshold(options.sharp_threshold);
    if (chosen.normal_noise_degrees < options.noisy_degrees) {
      // Clean normals: the components, unless they run across the creases.
      Segmentation components = segment_surfaces(graph, edge_flags, sharp_mask);
      chosen.sharp_edges_within = share_of_sharp_edges_within(rows, components);
      if (chosen.sharp_edges_within < options.leak_share) {
        chosen.core_threshold = options.sharp_threshold;
        if (info) *info = chosen;
        return components;
      }
    }
  }
  if (info) *info = chosen;
  // Every continuous edge has n_i·n_j >= w_s, so with a threshold at or below it every splat
  // is a core and the answer is the components (RobustSegmentOptions::core_threshold).
  if (!(chosen.core_threshold > options.sharp_threshold))
    return segment_surfaces(graph, edge_flags, sharp_mask);
  const std::size_t n = graph.num_points();
  std::vector<uint32_t> label(n), a(n), b(n);
  core_components(rows, find_cores(rows, normals, chosen.core_threshold), options.min_core_size, a,
                  b, label);
  grow(rows, label);
  label_the_rest(rows, label, a);

  // Labels are splat indices (roots); renumber in order of each surface's lowest splat.
  return renumber_surfaces(label, static_cast<uint32_t>(n));
}

}  // namespace splatkit::graph
