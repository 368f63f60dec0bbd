#include "graph/merge_coplanar_surfaces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "graph/fit_robust_plane.h"
#include "graph/renumber_surfaces.h"
#include "graph/surface_borders.h"
#include "graph/surface_members.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kMaxTestPoints = 4096;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The distance within which a plane holds splats: its scales, or a splat diameter (a step lower
// than the splats are wide is below what the sampling resolves).
double reach(const RobustPlane& plane, double scales) {
  return std::max(scales * plane.scale, plane.diameter);
}

// Whether the splats of `members` lie on `plane`: their median distance from it is within reach.
bool held(const RobustPlane& plane, std::span<const Vec3f> positions,
          std::span<const uint32_t> members, double scales) {
  const std::size_t step =
      std::max<std::size_t>(1, (members.size() + kMaxTestPoints - 1) / kMaxTestPoints);
  std::vector<double> d;
  for (std::size_t k = 0; k < members.size(); k += step)
    d.push_back(plane.distance(to_vec3d(positions[members[k]])));
  return median(std::move(d)) <= reach(plane, scales);
}

uint32_t root(std::vector<uint32_t>& parent, uint32_t s) {
  while (parent[s] != s) s = parent[s] = parent[parent[s]];
  return s;
}

}  // namespace

Segmentation merge_coplanar_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                     std::span<const Vec3f> normals, std::span<const float> radii,
                                     Segmentation seg, const CoplanarMergeOptions& o,
                                     CoplanarMergeInfo* info) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || radii.size() != n || seg.surface.size() != n)
    throw std::invalid_argument(
        "merge_coplanar_surfaces: one position, normal, radius and id per splat");
  const uint32_t count = seg.count();
  for (uint32_t s : seg.surface)
    if (s >= count) throw std::invalid_argument("merge_coplanar_surfaces: surface id out of range");
  CoplanarMergeInfo done;
  if (!(o.offset_scales > 0) || count < 2) {
    if (info) *info = done;
    return seg;
  }
  const SurfaceMembers groups = surface_members(seg.surface, count);
  std::vector<RobustPlane> planes(count);
  tbb::parallel_for(uint32_t{0}, count, [&](uint32_t s) {
    if (groups.of(s).size() >= std::max<uint32_t>(o.min_size, 3))
      planes[s] = fit_robust_plane(positions, normals, radii, groups.of(s), o.max_normal_degrees);
  });
  for (const RobustPlane& p : planes) done.planar += p.planar;

  // Adjacent pairs, larger first; each group is judged by its largest surface (its anchor).
  std::vector<std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>> order;  // ~large, ~small, a, b
  for (uint64_t pair : surface_borders(graph, seg.surface).pairs) {
    const uint32_t a = uint32_t(pair >> 32), b = uint32_t(pair);
    if (a > b) continue;
    const uint32_t sa = seg.sizes[a], sb = seg.sizes[b];
    order.emplace_back(~std::max(sa, sb), ~std::min(sa, sb), a, b);
  }
  std::sort(order.begin(), order.end());
  const double cos_angle = std::cos(o.max_angle_degrees * std::numbers::pi / 180);
  const double cos_disjoint = std::cos(o.max_disjoint_degrees * std::numbers::pi / 180);
  std::vector<uint32_t> parent(count);
  for (uint32_t s = 0; s < count; ++s) parent[s] = s;
  // Each group (by its root) with its splats, its size and the plane it is judged by: its
  // anchor's (the largest surface's), or with refit_groups the robust plane of all its splats.
  std::vector<std::vector<uint32_t>> members(count);
  std::vector<uint64_t> size(count);
  std::vector<uint32_t> anchor(count);
  std::vector<RobustPlane> plane = planes;
  std::vector<uint64_t> fitted(count);  // the group's size when its plane was fitted
  for (uint32_t s = 0; s < count; ++s) {
    anchor[s] = s;
    size[s] = fitted[s] = seg.sizes[s];
    if (o.refit_groups) members[s].assign(groups.of(s).begin(), groups.of(s).end());
  }
  auto of = [&](uint32_t r) {
    return o.refit_groups ? std::span<const uint32_t>(members[r]) : groups.of(anchor[r]);
  };
  // Larger group first; ties: the lower root.
  auto larger = [&](uint32_t ra, uint32_t rb) {
    return size[ra] != size[rb] ? size[ra] > size[rb] : ra < rb;
  };
  auto join = [&](uint32_t big, uint32_t small) {
    const uint32_t keep = std::min(big, small), gone = std::max(big, small);
    parent[gone] = keep;
    anchor[keep] = anchor[big];
    size[keep] = size[big] + size[small];
    if (o.refit_groups) {
      // The larger group's splats first, then the smaller's: the order (hence the fit's
      // sample) depends only on the joins made.
      std::vector<uint32_t> both = std::move(members[big]);
      both.insert(both.end(), members[small].begin(), members[small].end());
      members[small] = {};
      members[keep] = std::move(both);
      // Refitted once the group has grown by a tenth since its plane was fitted: pieces a
      // fraction of its size barely move it, and a facade takes in dozens of them.
      if (10 * size[keep] >= 11 * fitted[big]) {
        plane[keep] =
            fit_robust_plane(positions, normals, radii, members[keep], o.max_normal_degrees);
        fitted[keep] = size[keep];
      } else {
        plane[keep] = plane[big];
        fitted[keep] = fitted[big];
      }
    } else {
      plane[keep] = planes[anchor[keep]];
    }
    ++done.joined;
  };
  // Whether a minority group `small` is the relief of `big`: its splats' median lies within the
  // biweight's cut of the plane fitted to both together (the plane the joined group gets; the
  // minority's own offset widens the union's scale a little). Cheaply rejected first when it
  // lies beyond twice the cut of the larger's plane.
  auto relief_of = [&](uint32_t big, uint32_t small) {
    if (!held(plane[big], positions, of(small), 2 * o.relief_scales)) return false;
    if (!o.refit_groups) return held(plane[big], positions, of(small), o.relief_scales);
    std::vector<uint32_t> both = members[big];
    both.insert(both.end(), members[small].begin(), members[small].end());
    const RobustPlane joint =
        fit_robust_plane(positions, normals, radii, both, o.max_normal_degrees);
    return joint.planar && held(joint, positions, of(small), o.relief_scales);
  };
  // Passes over the pairs until none joins: a group that grew may now hold a neighbour as its
  // relief. A pair of groups already judged, neither changed since, is not judged again.
  std::vector<uint32_t> version(count, 0);
  std::set<std::array<uint32_t, 4>> rejected;
  for (bool joined = true; joined;) {
    joined = false;
    for (const auto& [neg_large, neg_small, a, b] : order) {
      uint32_t big = root(parent, a), small = root(parent, b);
      if (big == small) continue;
      if (!larger(big, small)) std::swap(big, small);
      const std::array<uint32_t, 4> key{big, version[big], small, version[small]};
      if (rejected.contains(key)) continue;
      // Within the larger's biweight support, a minority of the union is the larger's relief;
      // two surfaces of like size join at that offset only when each lies within the other's.
      const bool relief = o.relief_scales > o.offset_scales;
      const bool minority = 2 * size[small] <= size[big];
      if (!plane[big].planar || !plane[small].fitted ||
          std::abs(dot(plane[big].normal, plane[small].normal)) < cos_angle)
        continue;
      if (!held(plane[big], positions, of(small), o.offset_scales) &&
          !(relief && (minority ? relief_of(big, small)
                                : held(plane[big], positions, of(small), o.relief_scales) &&
                                      plane[small].planar &&
                                      held(plane[small], positions, of(big), o.relief_scales)))) {
        rejected.insert(key);
        continue;
      }
      join(big, small);
      ++version[std::min(big, small)];
      joined = true;
    }
  }
  if (o.join_disjoint) {
    // Groups that share no edge but lie on one plane (the wings of a facade either side of a
    // recessed middle): largest first, each held by the other's plane.
    std::vector<uint32_t> roots;
    for (uint32_t s = 0; s < count; ++s)
      if (root(parent, s) == s && plane[s].planar) roots.push_back(s);
    std::sort(roots.begin(), roots.end(), larger);
    for (std::size_t x = 0; x < roots.size(); ++x)
      for (std::size_t y = x + 1; y < roots.size(); ++y) {
        uint32_t big = root(parent, roots[x]), small = root(parent, roots[y]);
        if (big == small) continue;
        if (!larger(big, small)) std::swap(big, small);
        const RobustPlane &pb = plane[big], &ps = plane[small];
        // The centre test first: it is cheap and rejects nearly every pair.
        // A minority within the larger's biweight support is its relief here too.
        const double scales = std::max(o.offset_scales, o.relief_scales);
        const bool minority = o.relief_scales > o.offset_scales && 2 * size[small] <= size[big];
        if (!ps.planar || std::abs(dot(pb.normal, ps.normal)) < cos_disjoint ||
            pb.distance(ps.point) > 2 * reach(pb, minority ? scales : o.offset_scales))
          continue;
        if (!(held(pb, positions, of(small), o.offset_scales) &&
              held(ps, positions, of(big), o.offset_scales)) &&
            !(minority && relief_of(big, small)))
          continue;
        join(big, small);
        ++done.disjoint;
      }
  }
  std::vector<uint32_t> label(n);
  for (std::size_t i = 0; i < n; ++i) label[i] = root(parent, seg.surface[i]);
  if (info) *info = done;
  return renumber_surfaces(label, count);
}

}  // namespace splatkit::graph
