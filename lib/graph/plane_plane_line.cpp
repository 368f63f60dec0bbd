#include "graph/plane_plane_line.h"

#include <cmath>

namespace splatkit::graph {

std::optional<Line3> plane_plane_line(const Vec3f& c_i, const Vec3f& n_i, const Vec3f& c_j,
                                      const Vec3f& n_j, double min_sin2) {
  const Vec3d ni = to_vec3d(n_i), nj = to_vec3d(n_j);
  const Vec3d d = cross(ni, nj);
  const double aa = dot(ni, ni), bb = dot(nj, nj), ab = dot(ni, nj);
  // The determinant of eq. 4.6 is |n_i|²|n_j|² - (n_i·n_j)² = |n_i × n_j|²; compare it scaled.
  const double det = dot(d, d);
  if (!(det > min_sin2 * aa * bb)) return std::nullopt;  // also false for NaN and zero normals

  const Vec3d r = (to_vec3d(c_i) + to_vec3d(c_j)) * 0.5;
  const double hi = dot(ni, to_vec3d(c_i) - r);
  const double hj = dot(nj, to_vec3d(c_j) - r);
  const double ti = (hi * bb - hj * ab) / det;  // Cramer's rule on (4.6)
  const double tj = (hj * aa - hi * ab) / det;
  Line3 line;
  line.point = r + ni * ti + nj * tj;
  line.direction = d / std::sqrt(det);
  return line;
}

}  // namespace splatkit::graph
