#include "normals/splat_coverage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "splatkit/spatial_index.h"

namespace splatkit {

namespace {

bool inside(const SplatCloud& s, uint32_t i, const Vec3f& q) {
  const Vec3f d = q - s.positions[i];
  const Vec3f& n = s.normals[i];
  const float r = s.radii[i];
  const float h = dot(d, n);
  if (std::fabs(h) > 0.5f * r) return false;
  if (!s.has_ellipses()) return squared_norm(d) - h * h <= r * r;
  const Vec3f& u = s.axes[i];
  const float a = dot(d, u) / r, b = dot(d, cross(n, u)) / s.minor_radii[i];
  return a * a + b * b <= 1.0f;
}

}  // namespace

SplatCoverage splat_coverage(const SplatCloud& splats, std::span<const Vec3f> surface) {
  if (!splats.has_normals() || !splats.has_radii())
    throw std::invalid_argument("splat_coverage: the splats need normals and radii");
  const SpatialIndex index(splats.positions);
  float reach = 0;
  for (float r : splats.radii) reach = std::max(reach, r);
  reach *= std::sqrt(1.25f);  // the farthest point of the slab-bounded disc from its centre
  using Counts = std::pair<std::size_t, std::size_t>;  // uncovered, splat hits
  const Counts total = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, surface.size(), 1024), Counts{0, 0},
      [&](const tbb::blocked_range<std::size_t>& range, Counts c) {
        std::vector<uint32_t> near;
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          index.radius(surface[k], reach, near);
          std::size_t hits = 0;
          for (uint32_t i : near) hits += inside(splats, i, surface[k]) ? 1 : 0;
          c.first += hits == 0 ? 1 : 0;
          c.second += hits;
        }
        return c;
      },
      [](Counts a, const Counts& b) {
        a.first += b.first;
        a.second += b.second;
        return a;
      });
  SplatCoverage out;
  out.samples = surface.size();
  out.uncovered = total.first;
  out.mean_splats = surface.empty()
                        ? 0.0
                        : static_cast<double>(total.second) / static_cast<double>(surface.size());
  return out;
}

}  // namespace splatkit
