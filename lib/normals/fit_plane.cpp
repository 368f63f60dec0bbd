#include "normals/fit_plane.h"

#include <cmath>

#include "normals/neighborhood_pca.h"
#include "splatkit/pca_normal.h"

namespace splatkit {

bool triplet_plane(const Vec3f& a, const Vec3f& b, const Vec3f& c, float min_sine2, Plane& out) {
  const Vec3f u = b - a, v = c - a;
  const Vec3f n = cross(u, v);
  const float n2 = squared_norm(n);
  const float uv = squared_norm(u) * squared_norm(v);
  if (!(n2 > min_sine2 * uv)) return false;
  out.n = n / std::sqrt(n2);
  out.offset = dot(out.n, a);
  return true;
}

namespace {

// The PCA of the points of `local` within `band` of `plane`; false when fewer than 3.
bool inlier_pca(std::span<const Vec3f> local, const Plane& plane, float band, CovarianceEigen& e,
                double centroid[3]) {
  double s[3] = {0, 0, 0}, c[6] = {0, 0, 0, 0, 0, 0};
  std::size_t count = 0;
  for (const Vec3f& q : local) {
    if (!(std::fabs(dot(plane.n, q) - plane.offset) <= band)) continue;
    const double x = q.x, y = q.y, z = q.z;
    s[0] += x, s[1] += y, s[2] += z;
    c[0] += x * x, c[1] += x * y, c[2] += x * z, c[3] += y * y, c[4] += y * z, c[5] += z * z;
    ++count;
  }
  if (count < 3) return false;
  const double inv = 1.0 / static_cast<double>(count);
  c[0] -= s[0] * s[0] * inv, c[1] -= s[0] * s[1] * inv, c[2] -= s[0] * s[2] * inv;
  c[3] -= s[1] * s[1] * inv, c[4] -= s[1] * s[2] * inv, c[5] -= s[2] * s[2] * inv;
  e = pca_normal({c[0], c[1], c[2], c[3], c[4], c[5]});
  for (int a = 0; a < 3; ++a) centroid[a] = s[a] * inv;
  return true;
}

}  // namespace

bool refit_plane(std::span<const Vec3f> local, const Plane& plane, float band, Plane& out) {
  CovarianceEigen e;
  double centroid[3];
  if (!inlier_pca(local, plane, band, e, centroid)) return false;
  if (!(e.eigenvalues[1] > kCollinearRatio * e.eigenvalues[2])) return false;
  out.n = Vec3f{static_cast<float>(e.normal[0]), static_cast<float>(e.normal[1]),
                static_cast<float>(e.normal[2])};
  out.offset = static_cast<float>(e.normal[0] * centroid[0] + e.normal[1] * centroid[1] +
                                  e.normal[2] * centroid[2]);
  return true;
}

bool inliers_span_plane(std::span<const Vec3f> local, const Plane& plane, float band,
                        double min_spread) {
  CovarianceEigen e;
  double centroid[3];
  return inlier_pca(local, plane, band, e, centroid) &&
         e.eigenvalues[1] >= min_spread * e.eigenvalues[2];
}

}  // namespace splatkit
