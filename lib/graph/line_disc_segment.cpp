#include "graph/line_disc_segment.h"

#include <cmath>
#include <utility>

namespace splatkit::graph {

std::optional<Interval> solve_chord_quadratic(double a, double b, double c) {
  if (!(a > 0)) return std::nullopt;
  const double disc = b * b - a * c;
  if (!(disc >= 0)) return std::nullopt;
  // Citardauq form: no cancellation between -b and the root when |b| is large.
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a;
  double t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  return Interval{t0, t1};
}

std::optional<Interval> line_disc_segment(const Line3& line, const Vec3f& center,
                                          const Vec3f& normal, float radius) {
  if (!(radius > 0)) return std::nullopt;
  const Vec3d n = to_vec3d(normal);
  Vec3d p = line.point - to_vec3d(center);
  Vec3d d = line.direction;
  p = p - n * dot(p, n);
  d = d - n * dot(d, n);
  const double r = radius;
  // Perpendicular lines leave a projected direction of (near) zero length: no chord to speak of.
  if (!(dot(d, d) > 1e-24 * dot(line.direction, line.direction))) return std::nullopt;
  return solve_chord_quadratic(dot(d, d), dot(p, d), dot(p, p) - r * r);
}

}  // namespace splatkit::graph
