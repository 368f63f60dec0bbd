// splat_coverage: how well a cloud's splats cover a surface, measured at points of the true
// surface: the fraction of those points that lie in no splat, and the mean number of splats each
// lies in (overdraw; about 1.2 for circles around a perfect hexagonal sampling).
//
// A point q lies in splat (c, n, r) when |(q − c)·n| <= r / 2 (a slab around the splat's plane,
// wide enough for curvature and noise) and its projection onto the plane lies in the disc:
// in-plane distance <= r, or for an ellipse (axis u, v = n × u, semi-axes r and r_minor)
// ((q − c)·u / r)² + ((q − c)·v / r_minor)² <= 1.
//
// For tests and benchmarks (estimate-normals' splats against splat-synth's exact surfaces). Runs
// in parallel; the result does not depend on the thread count. Costs one kd-tree over the splat
// centres and one radius query (the largest radius) per surface point.
#pragma once

#include <cstddef>
#include <span>

#include "splatkit/splat_cloud.h"

namespace splatkit {

struct SplatCoverage {
  std::size_t samples = 0;
  std::size_t uncovered = 0;  // surface points in no splat
  double mean_splats = 0;     // mean number of splats a surface point lies in

  double uncovered_fraction() const {
    return samples == 0 ? 0.0 : static_cast<double>(uncovered) / static_cast<double>(samples);
  }
};

// splats: positions, normals (unit) and radii required, ellipses used when present; surface:
// points in the splats' local frame. Throws std::invalid_argument when normals or radii are
// missing.
SplatCoverage splat_coverage(const SplatCloud& splats, std::span<const Vec3f> surface);

}  // namespace splatkit
