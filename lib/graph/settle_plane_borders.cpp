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

// Whether splat i lies on surface t's side of the line where own's and t's planes cross, as
// its neighbours on t do: the side of the crease t's splats are on, along the direction in t's
// plane across the line (the crease's two faces are half-planes; the splat's neighbours on t lie
// on t's, beyond the line). False when they lie on the line.
bool on_side_of(const NeighborGraph& graph, std::span<const Vec3f> positions,
                const std::vector<uint32_t>& label, uint32_t i, const RobustPlane& own,
                const RobustPlane& other, uint32_t t) {
  const Vec3d p = to_vec3d(positions[i]);
  Vec3d mean;
  double count = 0;
  for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
    const uint32_t j = graph.neighbors[e];
    if (label[j] == t) mean += to_vec3d(positions[j]) - p, count += 1;
  }
  if (count == 0) return false;
  mean = mean / count;
  // A point x0 of the line, relative to p: n_a·x = h_a and n_b·x = h_b, d = n_a × n_b.
  const Vec3d &na = own.normal, &nb = other.normal;
  const Vec3d d = cross(na, nb);
  const double ha = dot(na, own.point - p), hb = dot(nb, other.point - p);
  const Vec3d x0 = cross(nb * ha - na * hb, d) / dot(d, d);
  const Vec3d across = cross(d, nb);  // in t's plane, perpendicular to the line
  const double side_p = dot(across, -x0), side_t = dot(across, mean - x0);
  return side_p * side_t > 0;
}

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
      const double own_distance = own.distance(p);
      const bool off_own = own_distance > o.offset_scales * own.scale;
      double best = own_distance;
      for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
        const uint32_t t = label[graph.neighbors[e]];
        if (t == label[i] || !planes[t].planar ||
            std::abs(dot(planes[t].normal, own.normal)) > cos_crease)
          continue;
        const double d = planes[t].distance(p);
        if (!(d < best || (d == best && target[i] != kStay && t < target[i])) ||
            d > o.offset_scales * planes[t].scale)
          continue;
        // Within its own plane's noise, the splat moves only when it is on t's side of the
        // crease and nearer t's plane in t's scales too (a face with relief, whose scale is
        // large, does not give its splats to a narrow ledge on it).
        if (!off_own && !(o.crease_side && d * own.scale < own_distance * planes[t].scale &&
                          on_side_of(graph, positions, label, i, own, planes[t], t)))
          continue;
        best = d, target[i] = t;
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
