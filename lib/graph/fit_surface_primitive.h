// fit_surface_primitive: the plane, sphere or cylinder that best explains a set of splats (one
// surface of a segmentation), fitted robustly — what refine_surface_borders judges border splats
// by.
//
// Each kind is fitted by iteratively reweighted least squares, three reweightings with Tukey's
// biweight at 4.685 robust scales (scale = 1.4826 × the median absolute residual), so splats of
// a neighbouring surface that leaked in (a border band, a few per cent) do not tilt the fit:
//   plane     PCA of the weighted positions; normal oriented like the splats' normals.
//   sphere    algebraic (Kåsa) fit |p|² + a·p + d = 0, linear least squares.
//   cylinder  axis: the direction the splats' normals are most orthogonal to (smallest
//             eigenvector of Σ w n nᵀ), then an algebraic circle across it — so it needs normals
//             good to a few degrees, which the robust fit tolerates on a minority of splats.
// The plane is fitted twice, from all splats and from those whose normals lie within 25° of the
// dominant direction, and the fit with the smaller scale kept: when two faces leaked into one
// surface, the least-squares plane lies between them and reweighting alone stays there. The
// plane wins unless a sphere or cylinder has a robust scale below 0.8 × the plane's (a plane is
// the limit of both, which their fits approach with huge, ill-conditioned radii).
// Residuals are Euclidean distances to the primitive (algebraic fits only choose it).
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include "graph/vec3d.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

enum class PrimitiveKind : uint8_t { kNone, kPlane, kSphere, kCylinder };

struct SurfacePrimitive {
  PrimitiveKind kind = PrimitiveKind::kNone;
  Vec3d point;         // plane: a point on it; sphere: the centre; cylinder: a point on the axis
  Vec3d direction;     // plane: unit normal, oriented like the splats' normals; cylinder: the
                       // unit axis (either sign)
  double radius = 0;   // sphere, cylinder
  double outward = 1;  // sphere, cylinder: +1 when the splats' normals point away from the centre
                       // or axis, -1 when towards it (a hole)
  double scale = std::numeric_limits<double>::infinity();  // robust residual scale of the fit,
                                                           // in the positions' units

  // Distance from p to the primitive, signed: > 0 on the side the normals point to. kNone:
  // +infinity.
  double signed_distance(const Vec3d& p) const;
  double distance(const Vec3d& p) const;
  // The oriented unit normal at the point of the primitive nearest to p; (0, 0, 0) on a sphere's
  // centre or a cylinder's axis, and for kNone.
  Vec3d normal_at(const Vec3d& p) const;
};

// positions, normals: #N each; members: the indices to fit (each < N, unchecked); fewer than 8
// give kind kNone. NaN normals count as zero (they neither orient nor find an axis). A sphere or
// cylinder whose system is singular (e.g. all points on a line) is not considered.
// Deterministic; O(members).
SurfacePrimitive fit_surface_primitive(std::span<const Vec3f> positions,
                                       std::span<const Vec3f> normals,
                                       std::span<const uint32_t> members);

}  // namespace splatkit::graph
