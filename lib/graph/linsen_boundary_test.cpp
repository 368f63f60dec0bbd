#include "graph/linsen_boundary_test.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "graph/vec3d.h"

namespace splatkit::graph {

BoundaryTestResult linsen_boundary_test(const Vec3f& c_i, const Vec3f& n_i,
                                        std::span<const Vec3f> neighbours, double alpha,
                                        std::vector<double>& scratch) {
  const Vec3d n = to_vec3d(n_i);
  // Duff et al.: continuous in n except across n.z = 0's sign flip, which is fine: the frame only
  // has to be the same for every neighbour of this one splat.
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  const Vec3d e1{1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  const Vec3d e2{b, sign + n.y * n.y * a, -n.y};

  scratch.clear();
  const Vec3d c = to_vec3d(c_i);
  for (const Vec3f& cj : neighbours) {
    const Vec3d w = to_vec3d(cj) - c;
    const Vec3d v = cross(w, n);  // eq. 4.2
    const double vv = dot(v, v);
    if (!(vv > 1e-12 * dot(w, w))) continue;
    scratch.push_back(std::atan2(dot(v, e2), dot(v, e1)));
  }

  BoundaryTestResult result;
  result.directions = static_cast<int>(scratch.size());
  constexpr double kTwoPi = 2 * std::numbers::pi;
  if (scratch.size() < 2) {
    result.max_gap = kTwoPi;
    result.boundary = true;
    return result;
  }
  std::sort(scratch.begin(), scratch.end());
  double max_gap = kTwoPi - (scratch.back() - scratch.front());
  for (std::size_t k = 1; k < scratch.size(); ++k)
    max_gap = std::max(max_gap, scratch[k] - scratch[k - 1]);
  result.max_gap = max_gap;
  result.boundary = max_gap > alpha;
  return result;
}

BoundaryTestResult linsen_boundary_test(const Vec3f& c_i, const Vec3f& n_i,
                                        std::span<const Vec3f> neighbours, double alpha) {
  std::vector<double> scratch;
  return linsen_boundary_test(c_i, n_i, neighbours, alpha, scratch);
}

}  // namespace splatkit::graph
