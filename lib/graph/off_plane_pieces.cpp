#include "graph/off_plane_pieces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "graph/lowest_root_union_find.h"

namespace splatkit::graph {

OffPlanePieces off_plane_pieces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                std::span<const Vec3f> normals, std::span<const float> radii,
                                const Segmentation& seg, double offset_scales,
                                double max_normal_degrees, double max_splat_degrees,
                                uint32_t min_size) {
  const std::size_t n = graph.num_points();
  const uint32_t count = seg.count();
  min_size = std::max<uint32_t>(min_size, 3);
  OffPlanePieces out{surface_members(seg.surface, count), std::vector<RobustPlane>(count), {}};
  const SurfaceMembers& groups = out.groups;
  std::vector<RobustPlane>& planes = out.planes;
  tbb::parallel_for(uint32_t{0}, count, [&](uint32_t s) {
    if (groups.of(s).size() >= 2 * min_size)  // room for a piece and the rest
      planes[s] = fit_robust_plane(positions, normals, radii, groups.of(s), max_normal_degrees);
  });
  const double cos_splat = std::cos(max_splat_degrees * std::numbers::pi / 180);
  std::vector<uint8_t> off(n, 0);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const RobustPlane& p = planes[seg.surface[i]];
    if (!p.planar || p.distance(to_vec3d(positions[i])) <= offset_scales * p.scale) return;
    const Vec3f& ni = normals[i];
    off[i] = !std::isfinite(ni.x + ni.y + ni.z) ||
             std::abs(dot(p.normal, to_vec3d(ni))) < cos_splat * norm(to_vec3d(ni));
  });
  std::vector<uint32_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = uint32_t(i);
  for (std::size_t i = 0; i < n; ++i) {
    if (!off[i]) continue;
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
      const uint32_t j = graph.neighbors[k];
      if (j > i && off[j] && seg.surface[j] == seg.surface[i]) unite(parent, uint32_t(i), j);
    }
  }
  // Pieces by their root (the lowest splat): members in ascending order.
  std::vector<uint32_t> root(n), size(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (off[i]) ++size[root[i] = find_root(parent, uint32_t(i))];
  std::vector<uint32_t> slot(n, 0xFFFFFFFFu);
  for (std::size_t i = 0; i < n; ++i) {
    if (!off[i] || size[root[i]] < min_size) continue;
    if (slot[root[i]] == 0xFFFFFFFFu)
      slot[root[i]] = uint32_t(out.pieces.size()), out.pieces.emplace_back();
    out.pieces[slot[root[i]]].push_back(uint32_t(i));
  }
  return out;
}

}  // namespace splatkit::graph
