#include "graph/fit_robust_plane.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kMaxFitPoints = 4096;
constexpr int kReweightings = 10;
constexpr double kTukey = 4.685;

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

RobustPlane fit_robust_plane(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                             std::span<const float> radii, std::span<const uint32_t> members,
                             double max_normal_degrees) {
  RobustPlane plane;
  if (members.size() < 3) return plane;
  const std::size_t step =
      std::max<std::size_t>(1, (members.size() + kMaxFitPoints - 1) / kMaxFitPoints);
  std::vector<uint32_t> sample;
  for (std::size_t k = 0; k < members.size(); k += step) sample.push_back(members[k]);
  // Relative to one member: far from the origin, float positions keep their digits.
  const Vec3d origin = to_vec3d(positions[sample[0]]);
  std::vector<Vec3d> p(sample.size());
  for (std::size_t k = 0; k < sample.size(); ++k) p[k] = to_vec3d(positions[sample[k]]) - origin;
  std::vector<double> w(sample.size(), 1.0), r(sample.size());
  for (int pass = 0; pass <= kReweightings; ++pass) {
    double sw = 0;
    Vec3d c;
    for (std::size_t k = 0; k < p.size(); ++k) sw += w[k], c += p[k] * w[k];
    if (!(sw > 0)) break;  // every weight 0 cannot happen (the median residual has weight > 0)
    c = c / sw;
    std::array<double, 6> cov{};
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Vec3d d = p[k] - c;
      cov[0] += w[k] * d.x * d.x, cov[1] += w[k] * d.x * d.y, cov[2] += w[k] * d.x * d.z;
      cov[3] += w[k] * d.y * d.y, cov[4] += w[k] * d.y * d.z, cov[5] += w[k] * d.z * d.z;
    }
    const std::array<double, 3> n = pca_normal(cov).normal;
    plane.point = c;
    plane.normal = {n[0], n[1], n[2]};
    for (std::size_t k = 0; k < p.size(); ++k) r[k] = plane.distance(p[k]);
    const double previous = plane.scale;
    plane.scale = 1.4826 * median(r);
    const double cut = kTukey * plane.scale;
    // Exactly planar, or settled (the weights would barely change).
    if (!(cut > 0) || (pass > 0 && plane.scale > 0.99 * previous)) break;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const double u = r[k] / cut;
      w[k] = u < 1 ? (1 - u * u) * (1 - u * u) : 0;
    }
  }
  plane.fitted = true;
  plane.point += origin;
  Vec3d lo = p[0], hi = p[0];
  for (const Vec3d& q : p) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
  plane.scale = std::max(plane.scale, 1e-5 * norm(hi - lo));
  std::vector<double> diameter, cosine;
  for (uint32_t i : sample) {
    diameter.push_back(2.0 * double(radii[i]));
    const Vec3d n = to_vec3d(normals[i]);
    if (finite(normals[i]) && norm(n) > 0)
      cosine.push_back(std::abs(dot(plane.normal, n)) / norm(n));
  }
  plane.diameter = median(std::move(diameter));
  // The median |cos| is the cosine of the median angle.
  plane.planar = cosine.empty() ||
                 median(std::move(cosine)) >= std::cos(max_normal_degrees * std::numbers::pi / 180);
  return plane;
}

}  // namespace splatkit::graph
