// fit_robust_plane: the plane a surface of a segmentation lies on, fitted so that its relief and
// a leaked band do not tilt it, with how far its splats spread about it — what
// split_planar_surfaces and merge_coplanar_surfaces judge surfaces by.
//
// Least squares (PCA of the positions) reweighted with Tukey's biweight at 4.685 robust scales,
// scale = 1.4826 × the median absolute distance from the plane, until the scale stops shrinking
// by 1 % (at most ten times: a face standing on a larger one pulls the first fit towards it, and
// three reweightings left a scale 20 times the noise). On a noisy scan the scale is the noise;
// on a facade it is the noise and the relief (window reveals, sills). At least 1e-5 of the
// sample's extent (a rounding floor, so that an exactly planar surface still holds its own
// splats). The surface is *planar* when the median angle between its splats' normals (either
// sign; NaN normals left out) and the plane's normal is at most max_normal_degrees: on a curved
// patch the normals turn away from any one plane, on a noisy or relieved plane they scatter
// about it (a cylinder arc of up to about twice that angle still passes: the plane tangent at
// its middle holds half its normals).
#pragma once

#include <cstdint>
#include <span>

#include "graph/vec3d.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct RobustPlane {
  bool fitted = false;  // false for fewer than 3 members
  bool planar = false;
  Vec3d point;          // on the plane
  Vec3d normal;         // unit, either sign
  double scale = 0;     // robust residual scale, the positions' units
  double diameter = 0;  // median splat diameter (2 r) of the sample

  double distance(const Vec3d& p) const { return std::abs(dot(normal, p - point)); }
};

// positions, normals, radii: #N each; members: the surface's splat indices (each < N, unchecked),
// of which at most 4096 spread evenly over the list are used. Deterministic; O(members).
RobustPlane fit_robust_plane(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                             std::span<const float> radii, std::span<const uint32_t> members,
                             double max_normal_degrees);

}  // namespace splatkit::graph
