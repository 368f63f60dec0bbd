// The part of a line inside an elliptic splat ([IvoMSc] §4.2.2, eqs. 4.8–4.11;
// docs/references.md).
#pragma once

#include <optional>

#include "graph/geometry_types.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// Returns the closed parameter interval [t0, t1] of the points line.point + t line.direction whose
// coordinates in the splat's frame, u = (P - C)·axis_u / semi_u and v = (P - C)·axis_v / semi_v,
// satisfy u² + v² <= 1: the roots of A t² + 2B t + C = 0 (eq. 4.11) with
//   A = d_u²/a² + d_v²/b²,  B = P_ou d_u/a² + P_ov d_v/b²,  C = P_ou²/a² + P_ov²/b² - 1,
// (P_ou, P_ov), (d_u, d_v) the line's point relative to C and its direction in the (axis_u,
// axis_v) frame (eq. 4.8). Components along the normal are dropped, so for a line in the splat's
// plane this is the chord, otherwise the chord of its projection onto the plane. axis_u, axis_v:
// unit, orthogonal, in the plane; semi-axes a = semi_u, b = semi_v > 0. Returns std::nullopt when
// the line misses the ellipse, is perpendicular to the plane, a semi-axis is <= 0, or on NaN input.
// With a == b and any in-plane orthonormal axes the result equals line_disc_segment's.
std::optional<Interval> line_ellipse_segment(const Line3& line, const Vec3f& center,
                                             const Vec3f& axis_u, const Vec3f& axis_v, float semi_u,
                                             float semi_v);

}  // namespace splatkit::graph
