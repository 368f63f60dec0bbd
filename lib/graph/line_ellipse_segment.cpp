#include "graph/line_ellipse_segment.h"

#include "graph/line_disc_segment.h"

namespace splatkit::graph {

std::optional<Interval> line_ellipse_segment(const Line3& line, const Vec3f& center,
                                             const Vec3f& axis_u, const Vec3f& axis_v, float semi_u,
                                             float semi_v) {
  if (!(semi_u > 0) || !(semi_v > 0)) return std::nullopt;
  const Vec3d u = to_vec3d(axis_u), v = to_vec3d(axis_v);
  const Vec3d p = line.point - to_vec3d(center);
  // Dividing by the semi-axes first turns eq. 4.11 into the unit-circle case of eq. 4.12.
  const double pu = dot(p, u) / semi_u, pv = dot(p, v) / semi_v;
  const double du = dot(line.direction, u) / semi_u, dv = dot(line.direction, v) / semi_v;
  const double a = du * du + dv * dv;
  const double scale =
      dot(line.direction, line.direction) / (double(semi_u) * semi_u + double(semi_v) * semi_v);
  if (!(a > 1e-24 * scale)) return std::nullopt;
  return solve_chord_quadratic(a, pu * du + pv * dv, pu * pu + pv * pv - 1);
}

}  // namespace splatkit::graph
