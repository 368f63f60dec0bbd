#include "graph/settle_plane_borders.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "graph/fit_robust_plane.h"
#include "graph/renumber_surfaces.h"
#include "graph/surface_members.h"

namespace splatkit::graph {
namespace {

constexpr uint32_t kStay = 0xFFFFFFFFu;

}  // namespace

Segmentation settle_plane_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                  std::span<const Vec3f> normals, std::span<const float> radii,
                                  Segmentation seg, const SettlePlaneBordersOptions& o,
                                  uint64_t* moved) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || radii.size() != n || seg.surface.size() != n)
    throw std::invalid_argument(
        "settle_plane_borders: one position, normal, radius and id per splat");
  const uint32_t count = seg.count();
  for (uint32_t s : seg.surface)
    if (s >= count) throw std::invalid_argument("settle_plane_borders: surface id out of range");
  if (moved) *moved = 0;
  if (!(o.offset_scales > 0) || o.rounds == 0 || count < 2) return seg;
  const SurfaceMembers groups = surface_members(seg.surface, count);
  std::vector<RobustPlane> planes(count);
  tbb::parallel_for(uint32_t{0}, count, [&](uint32_t s) {
    if (groups.of(s).size() >= std::max<uint32_t>(o.min_size, 3))
      planes[s] = fit_robust_plane(positions, normals, radii, groups.of(s), o.max_normal_degrees);
  });
  const double cos_crease = std::cos(o.min_crease_degrees * std::numbers::pi / 180);
  std::vector<uint32_t> label = std::move(seg.surface);
  // The first round's candidates: the splats of planar surfaces with a neighbour elsewhere.
  std::vector<uint8_t> border(n, 0);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (!planes[label[i]].planar) return;
    for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
      if (label[graph.neighbors[e]] != label[i]) {
        border[i] = 1;
        return;
      }
  });
  std::vector<uint32_t> candidates;
  for (std::size_t i = 0; i < n; ++i)
    if (border[i]) candidates.push_back(uint32_t(i));
  std::vector<uint32_t> target(n, kStay);
  uint64_t moves = 0;
  for (uint32_t round = 0; round < o.rounds && !candidates.empty(); ++round) {
    // Judged on the labels of the round's start: any order gives the same targets.
    tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t k) {
      const uint32_t i = candidates[k];
      target[i] = kStay;
      const RobustPlane& own = planes[label[i]];
      if (!own.planar) return;
      const Vec3d p = to_vec3d(positions[i]);
      double best = own.distance(p);
      if (best <= o.offset_scales * own.scale) return;
      for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
        const uint32_t t = label[graph.neighbors[e]];
        if (t == label[i] || !planes[t].planar ||
            std::abs(dot(planes[t].normal, own.normal)) > cos_crease)
          continue;
        const double d = planes[t].distance(p);
        if (d > o.offset_scales * planes[t].scale) continue;
        if (d < best || (d == best && target[i] != kStay && t < target[i])) best = d, target[i] = t;
      }
    });
    std::vector<uint32_t> changed;
    for (uint32_t i : candidates)
      if (target[i] != kStay) changed.push_back(i);
    if (changed.empty()) break;
    for (uint32_t i : changed) label[i] = target[i], target[i] = kStay;
    moves += changed.size();
    // Next round: the splats that changed and their neighbours.
    std::vector<uint32_t> next;
    for (uint32_t i : changed) {
      next.push_back(i);
      for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
        next.push_back(graph.neighbors[e]);
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    candidates = std::move(next);
  }
  if (moved) *moved = moves;
  return renumber_surfaces(label, count);
}

}  // namespace splatkit::graph
