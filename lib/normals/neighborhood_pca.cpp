#include "normals/neighborhood_pca.h"

#include <array>
#include <cmath>
#include <limits>

#include "splatkit/pca_normal.h"

namespace splatkit {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

Vec3f to_vec3f(const std::array<double, 3>& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

}  // namespace

Vec3f canonical_sign(const Vec3f& n) {
  int largest = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(n[a]) > std::fabs(n[largest])) largest = a;
  return n[largest] < 0 ? -n : n;
}

PcaNormal neighborhood_pca(std::span<const Vec3f> positions, std::span<const uint32_t> indices) {
  PcaNormal out;
  // One pass about the first point (the query itself in a kNN row): the sums stay small, so the
  // double-precision C = S - s sᵀ / count loses nothing to cancellation at neighbourhood scale.
  const uint32_t* first = indices.data();
  const uint32_t* end = first + indices.size();
  while (first != end && *first == kNone) ++first;
  if (first == end) return out;
  const Vec3f o = positions[*first];
  double sx = 0, sy = 0, sz = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  std::size_t count = 0;
  for (const uint32_t* it = first; it != end; ++it) {
    if (*it == kNone) continue;
    const Vec3f& p = positions[*it];
    const double dx = double{p.x} - o.x, dy = double{p.y} - o.y, dz = double{p.z} - o.z;
    sx += dx, sy += dy, sz += dz;
    xx += dx * dx, xy += dx * dy, xz += dx * dz;
    yy += dy * dy, yz += dy * dz, zz += dz * dz;
    ++count;
  }
  if (count < 2) return out;
  const double inv = 1.0 / static_cast<double>(count);
  xx -= sx * sx * inv, xy -= sx * sy * inv, xz -= sx * sz * inv;
  yy -= sy * sy * inv, yz -= sy * sz * inv, zz -= sz * sz * inv;
  const CovarianceEigen eigen = pca_normal({xx, xy, xz, yy, yz, zz});
  for (int a = 0; a < 3; ++a) out.eigenvalues[a] = eigen.eigenvalues[a];
  out.degenerate = !(out.eigenvalues[1] > kCollinearRatio * out.eigenvalues[2]);
  out.normal = canonical_sign(to_vec3f(eigen.normal));
  out.axis = to_vec3f(eigen.axis);
  if (!(out.eigenvalues[2] > 0)) out.normal = {0, 0, 1};
  return out;
}

bool is_thread(const PcaNormal& pca, std::span<const Vec3f> positions, uint32_t centre,
               std::span<const uint32_t> indices) {
  if (pca.degenerate || pca.eigenvalues[1] < kThinRatio * pca.eigenvalues[2]) return true;
  if (!(pca.eigenvalues[1] < kThreadCheckRatio * pca.eigenvalues[2])) return false;
  const Vec3f& c = positions[centre];
  double sin2 = 0;
  std::size_t count = 0;
  for (const uint32_t j : indices) {
    if (j == kNone || j == centre) continue;
    const Vec3f d = positions[j] - c;
    const double d2 = squared_norm(d);
    if (!(d2 > 0)) continue;  // a duplicate: no direction
    const double along = dot(d, pca.axis);
    sin2 += 1.0 - along * along / d2;
    ++count;
  }
  return count > 0 && sin2 < kThreadSin2 * static_cast<double>(count);
}

}  // namespace splatkit
