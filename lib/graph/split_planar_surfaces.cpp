#include "graph/split_planar_surfaces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "graph/fit_robust_plane.h"
#include "graph/lowest_root_union_find.h"
#include "graph/off_plane_pieces.h"
#include "graph/plane_residual_scale.h"
#include "graph/renumber_surfaces.h"
#include "graph/surface_members.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

// The splats of `piece` in two halves by their normals (each turned to the side of `towards`;
// NaN normals in neither): either side of the mean across the normals' main axis of spread.
std::array<std::vector<uint32_t>, 2> halves(const std::vector<uint32_t>& piece,
                                            std::span<const Vec3f> normals, const Vec3d& towards) {
  std::vector<Vec3d> ns;
  std::vector<uint32_t> which;
  Vec3d mean;
  for (uint32_t i : piece) {
    if (!finite(normals[i])) continue;
    Vec3d v = to_vec3d(normals[i]);
    if (dot(v, towards) < 0) v = -v;
    ns.push_back(v);
    which.push_back(i);
    mean += v;
  }
  std::array<std::vector<uint32_t>, 2> out;
  if (ns.empty()) return out;
  mean = mean / double(ns.size());
  std::array<double, 6> cov{};
  for (const Vec3d& v : ns) {
    const Vec3d d = v - mean;
    cov[0] += d.x * d.x, cov[1] += d.x * d.y, cov[2] += d.x * d.z;
    cov[3] += d.y * d.y, cov[4] += d.y * d.z, cov[5] += d.z * d.z;
  }
  const std::array<double, 3> a = pca_normal(cov).axis;
  const Vec3d axis{a[0], a[1], a[2]};
  for (std::size_t k = 0; k < ns.size(); ++k)
    out[dot(ns[k] - mean, axis) < 0 ? 0 : 1].push_back(which[k]);
  return out;
}

// The connected parts of `splats` (ascending) over the graph's edges between them, each
// ascending, in the order of their lowest splat; parts under min_size left out.
std::vector<std::vector<uint32_t>> connected(const NeighborGraph& graph,
                                             const std::vector<uint32_t>& splats,
                                             uint32_t min_size) {
  std::vector<uint32_t> parent(splats.size());
  for (std::size_t k = 0; k < splats.size(); ++k) parent[k] = uint32_t(k);
  for (std::size_t k = 0; k < splats.size(); ++k) {
    const uint32_t i = splats[k];
    for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
      const uint32_t j = graph.neighbors[e];
      if (j <= i) continue;
      const auto it = std::lower_bound(splats.begin(), splats.end(), j);
      if (it != splats.end() && *it == j) unite(parent, uint32_t(k), uint32_t(it - splats.begin()));
    }
  }
  std::vector<std::vector<uint32_t>> parts;
  std::vector<uint32_t> slot(splats.size(), 0xFFFFFFFFu), size(splats.size(), 0);
  for (std::size_t k = 0; k < splats.size(); ++k) ++size[find_root(parent, uint32_t(k))];
  for (std::size_t k = 0; k < splats.size(); ++k) {
    const uint32_t r = find_root(parent, uint32_t(k));
    if (size[r] < min_size) continue;
    if (slot[r] == 0xFFFFFFFFu) slot[r] = uint32_t(parts.size()), parts.emplace_back();
    parts[slot[r]].push_back(splats[k]);
  }
  return parts;
}

// The noise of `part`'s splats about planes through their neighbours in the part (each splat
// left out of its own plane): 1.4826 × the median residual over up to 512 of them; infinity when
// none has 5 such neighbours. `part` ascending.
double local_scale(const NeighborGraph& graph, std::span<const Vec3f> positions,
                   const std::vector<uint32_t>& part) {
  const std::size_t step = std::max<std::size_t>(1, (part.size() + 511) / 512);
  PlaneResidualScale scale;
  for (std::size_t k = 0; k < part.size(); k += step) {
    const uint32_t i = part[k];
    const Vec3d p = to_vec3d(positions[i]);
    for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
      const uint32_t j = graph.neighbors[e];
      if (std::binary_search(part.begin(), part.end(), j)) scale.add(to_vec3d(positions[j]) - p);
    }
    scale.close();
  }
  return scale.scale();
}

}  // namespace

Segmentation split_planar_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                   std::span<const Vec3f> normals, std::span<const float> radii,
                                   Segmentation seg, const SplitPlanesOptions& o, uint32_t* split) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || radii.size() != n || seg.surface.size() != n)
    throw std::invalid_argument(
        "split_planar_surfaces: one position, normal, radius and id per splat");
  const uint32_t count = seg.count();
  for (uint32_t s : seg.surface)
    if (s >= count) throw std::invalid_argument("split_planar_surfaces: surface id out of range");
  if (split) *split = 0;
  if (!(o.offset_scales > 0)) return seg;
  const uint32_t min_size = std::max<uint32_t>(o.min_size, 3);
  OffPlanePieces off = off_plane_pieces(graph, positions, normals, radii, seg, o.offset_scales,
                                        o.max_normal_degrees, o.max_splat_degrees, min_size);
  const SurfaceMembers& groups = off.groups;
  const std::vector<RobustPlane>& planes = off.planes;
  std::vector<std::vector<uint32_t>>& pieces = off.pieces;
  const double cos_splat = std::cos(o.max_splat_degrees * std::numbers::pi / 180);
  // A surface that is not planar is a piece of itself (a wall and the ledge on it that the
  // segmentation joined).
  const std::size_t off_pieces = pieces.size();
  for (uint32_t s = 0; s < count; ++s)
    if (planes[s].fitted && !planes[s].planar)
      pieces.emplace_back(groups.of(s).begin(), groups.of(s).end());
  // A piece that is not planar (two faces, as the two slopes of a gable) is halved by its
  // normals, across their direction of largest spread, and the halves' connected parts judged.
  std::vector<std::vector<std::vector<uint32_t>>> parts(pieces.size());
  tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t k) {
    const RobustPlane& whole = planes[seg.surface[pieces[k][0]]];
    const bool off_a_plane = k < off_pieces;
    auto judge = [&](const std::vector<uint32_t>& piece) {
      const RobustPlane own =
          fit_robust_plane(positions, normals, radii, piece,
                           off_a_plane ? o.max_normal_degrees : o.max_face_degrees);
      if (!own.planar) return false;
      if (off_a_plane) return std::abs(dot(own.normal, whole.normal)) < cos_splat;
      // A face of a surface that is not planar: its splats lie on its plane within their local
      // noise (a narrow strip of a curved surface passes the normals' test, not this one).
      return own.scale <= 2 * local_scale(graph, positions, piece) + 1e-9;
    };
    if (off_a_plane && judge(pieces[k])) {
      parts[k].push_back(pieces[k]);
      return;
    }
    for (const std::vector<uint32_t>& half : halves(pieces[k], normals, whole.normal))
      for (std::vector<uint32_t>& part : connected(graph, half, min_size))
        if (judge(part)) parts[k].push_back(std::move(part));
  });
  std::vector<uint32_t> label = std::move(seg.surface);
  uint32_t labels = count;
  for (auto& piece_parts : parts)
    for (const std::vector<uint32_t>& part : piece_parts) {
      for (uint32_t i : part) label[i] = labels;
      ++labels;
    }
  if (split) *split = labels - count;
  return renumber_surfaces(label, labels);
}

}  // namespace splatkit::graph
