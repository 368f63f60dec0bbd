// The part of a line inside a circular splat ([IvoMSc] §4.2.2, eq. 4.12;
// docs/references.md).
#pragma once

#include <optional>

#include "graph/geometry_types.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// Returns the closed parameter interval [t0, t1] of the points line.point + t line.direction that
// lie in the disc {P : (P - center)·normal = 0, |P - center| <= radius}, i.e. the roots of
// A t² + 2B t + C = 0 with A = d·d, B = P_o·d, C = P_o·P_o - r² (eq. 4.12), where P_o and d are the
// line's point (relative to the centre) and direction with their components along the normal
// removed. For a line in the disc's plane (what plane_plane_line gives, up to rounding) this is
// exactly the chord; for another line it is the chord of its orthogonal projection onto the plane.
// t is in the line's parametrisation (a length when the direction is a unit vector).
// normal: unit. Returns std::nullopt when the line misses the disc, when it is perpendicular to the
// plane (its projection is a point), when radius <= 0, or on NaN input. A tangent line gives
// t0 == t1.
std::optional<Interval> line_disc_segment(const Line3& line, const Vec3f& center,
                                          const Vec3f& normal, float radius);

// The positive-discriminant roots of A t² + 2B t + C = 0 in ascending order (shared with
// line_ellipse_segment); std::nullopt when there are none or A <= 0.
std::optional<Interval> solve_chord_quadratic(double a, double b, double c);

}  // namespace splatkit::graph
