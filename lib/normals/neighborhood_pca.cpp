#include "normals/neighborhood_pca.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

namespace splatkit {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

Vec3f to_vec3f(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
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
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (uint32_t idx : indices) {
    if (idx == kNone) continue;
    const Vec3f& p = positions[idx];
    mean += Eigen::Vector3d(p.x, p.y, p.z);
    ++count;
  }
  if (count < 2) return out;
  mean /= static_cast<double>(count);

  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (uint32_t idx : indices) {
    if (idx == kNone) continue;
    const Vec3f& p = positions[idx];
    const double dx = p.x - mean.x(), dy = p.y - mean.y(), dz = p.z - mean.z();
    xx += dx * dx, xy += dx * dy, xz += dx * dz;
    yy += dy * dy, yz += dy * dz, zz += dz * dz;
  }
  Eigen::Matrix3d c;
  c << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(c);
  const Eigen::Vector3d& values = solver.eigenvalues();
  for (int a = 0; a < 3; ++a) out.eigenvalues[a] = std::max(values[a], 0.0);
  out.degenerate = !(out.eigenvalues[1] > kCollinearRatio * out.eigenvalues[2]);
  const Eigen::Vector3d n = solver.eigenvectors().col(0);
  const Eigen::Vector3d axis = solver.eigenvectors().col(2);
  const double nn = n.norm(), an = axis.norm();
  // computeDirect returns unit vectors; the guard keeps a NaN out whatever the solver does.
  if (std::isfinite(nn) && nn > 0) out.normal = canonical_sign(to_vec3f(n / nn));
  if (std::isfinite(an) && an > 0) out.axis = to_vec3f(axis / an);
  if (out.eigenvalues[2] <= 0) out.normal = {0, 0, 1};
  return out;
}

}  // namespace splatkit
