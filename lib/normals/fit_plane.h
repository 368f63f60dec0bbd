// Planes through a point's neighbourhood, for the robust normal fit (Li et al. 2010): a candidate
// through three neighbours, and the PCA plane refitted over the neighbours within a band of it.
#pragma once

#include <span>

#include "splatkit/vec3.h"

namespace splatkit {

struct Plane {
  Vec3f n;       // unit
  float offset;  // n·x = offset, x relative to the query point
};

// The plane through three points, or false when they are (nearly) collinear: the squared sine of
// the angle at `a` is below min_sine2.
bool triplet_plane(const Vec3f& a, const Vec3f& b, const Vec3f& c, float min_sine2, Plane& out);

// The PCA plane of the points of `local` whose residual to `plane` is at most `band`, through
// their centroid; false when fewer than 3 or they are degenerate (collinear).
bool refit_plane(std::span<const Vec3f> local, const Plane& plane, float band, Plane& out);

// Whether the points of `local` within `band` of `plane` spread over a patch rather than a line:
// the middle eigenvalue of their covariance at least `min_spread` times the largest (a straight
// strip of width w and length L: about 0.1 at w = L / 3; a half disc: 0.28).
bool inliers_span_plane(std::span<const Vec3f> local, const Plane& plane, float band,
                        double min_spread);

}  // namespace splatkit
