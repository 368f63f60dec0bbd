#include "graph/fit_surface_primitive.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

// Solves the symmetric positive definite system a x = b (row-major n×n) by Gaussian elimination
// with partial pivoting; false when singular.
template <int N>
bool solve(std::array<double, N * N> a, std::array<double, N> b, std::array<double, N>& x) {
  double big = 0;
  for (double v : a) big = std::max(big, std::abs(v));
  if (!(big > 0)) return false;
  for (int c = 0; c < N; ++c) {
    int p = c;
    for (int r = c + 1; r < N; ++r)
      if (std::abs(a[r * N + c]) > std::abs(a[p * N + c])) p = r;
    if (!(std::abs(a[p * N + c]) > 1e-13 * big)) return false;
    if (p != c) {
      for (int k = 0; k < N; ++k) std::swap(a[p * N + k], a[c * N + k]);
      std::swap(b[p], b[c]);
    }
    for (int r = c + 1; r < N; ++r) {
      const double f = a[r * N + c] / a[c * N + c];
      for (int k = c; k < N; ++k) a[r * N + k] -= f * a[c * N + k];
      b[r] -= f * b[c];
    }
  }
  for (int r = N - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < N; ++k) s -= a[r * N + k] * x[k];
    x[r] = s / a[r * N + r];
  }
  return true;
}

struct Sample {
  Vec3d p;  // relative to the centroid
  Vec3d n;  // unit normal, or 0
};

Vec3d unit(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

SurfacePrimitive fit_plane(std::span<const Sample> s, std::span<const double> w) {
  double sw = 0;
  Vec3d c;
  for (std::size_t k = 0; k < s.size(); ++k) sw += w[k], c += s[k].p * w[k];
  if (!(sw > 0)) return {};
  c = c / sw;
  std::array<double, 6> cov{};
  Vec3d nsum;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3d d = s[k].p - c;
    cov[0] += w[k] * d.x * d.x, cov[1] += w[k] * d.x * d.y, cov[2] += w[k] * d.x * d.z;
    cov[3] += w[k] * d.y * d.y, cov[4] += w[k] * d.y * d.z, cov[5] += w[k] * d.z * d.z;
    nsum += s[k].n * w[k];
  }
  Vec3d n = unit(pca_normal(cov).normal);
  if (dot(n, nsum) < 0) n = -n;
  SurfacePrimitive f;
  f.kind = PrimitiveKind::kPlane;
  f.point = c;
  f.direction = n;
  return f;
}

// Algebraic sphere (Kasa): |p|² + a·p + d = 0 in the least-squares sense.
SurfacePrimitive fit_sphere(std::span<const Sample> s, std::span<const double> w) {
  std::array<double, 16> m{};
  std::array<double, 4> b{};
  for (std::size_t k = 0; k < s.size(); ++k) {
    const std::array<double, 4> v{s[k].p.x, s[k].p.y, s[k].p.z, 1};
    const double q = dot(s[k].p, s[k].p);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) m[r * 4 + c] += w[k] * v[r] * v[c];
      b[r] -= w[k] * q * v[r];
    }
  }
  std::array<double, 4> x{};
  if (!solve<4>(m, b, x)) return {};
  const Vec3d o{-x[0] / 2, -x[1] / 2, -x[2] / 2};
  const double r2 = dot(o, o) - x[3];
  if (!(r2 > 0)) return {};
  SurfacePrimitive f;
  f.kind = PrimitiveKind::kSphere;
  f.point = o;
  f.radius = std::sqrt(r2);
  double out = 0;
  for (std::size_t k = 0; k < s.size(); ++k) out += w[k] * dot(s[k].n, s[k].p - o);
  f.outward = out < 0 ? -1 : 1;
  return f;
}

// Axis: the direction the normals are orthogonal to; then a Kasa circle in the plane across it.
SurfacePrimitive fit_cylinder(std::span<const Sample> s, std::span<const double> w) {
  std::array<double, 6> nn{};
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3d& n = s[k].n;
    nn[0] += w[k] * n.x * n.x, nn[1] += w[k] * n.x * n.y, nn[2] += w[k] * n.x * n.z;
    nn[3] += w[k] * n.y * n.y, nn[4] += w[k] * n.y * n.z, nn[5] += w[k] * n.z * n.z;
  }
  const Vec3d a = unit(pca_normal(nn).normal);
  // u, v: an orthonormal basis across the axis.
  const Vec3d helper = std::abs(a.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  Vec3d u = cross(a, helper);
  u = u / norm(u);
  const Vec3d v = cross(a, u);
  std::array<double, 9> m{};
  std::array<double, 3> b{};
  for (std::size_t k = 0; k < s.size(); ++k) {
    const std::array<double, 3> q{dot(s[k].p, u), dot(s[k].p, v), 1};
    const double r = q[0] * q[0] + q[1] * q[1];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i * 3 + j] += w[k] * q[i] * q[j];
      b[i] -= w[k] * r * q[i];
    }
  }
  std::array<double, 3> x{};
  if (!solve<3>(m, b, x)) return {};
  const double cu = -x[0] / 2, cv = -x[1] / 2, r2 = cu * cu + cv * cv - x[2];
  if (!(r2 > 0)) return {};
  SurfacePrimitive f;
  f.kind = PrimitiveKind::kCylinder;
  f.point = u * cu + v * cv;
  f.direction = a;
  f.radius = std::sqrt(r2);
  double out = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3d d = s[k].p - f.point;
    out += w[k] * dot(s[k].n, d - a * dot(d, a));
  }
  f.outward = out < 0 ? -1 : 1;
  return f;
}

// Iteratively reweighted: Tukey's biweight at 4.685 robust scales (1.4826 × median |r|).
template <class Fit>
SurfacePrimitive fit_robust(std::span<const Sample> s, Fit&& fit, int iterations,
                            std::vector<double> w) {
  std::vector<double> r(s.size()), sorted;
  SurfacePrimitive f;
  for (int it = 0; it <= iterations; ++it) {
    const SurfacePrimitive g = fit(s, w);
    if (g.kind == PrimitiveKind::kNone) return f;
    f = g;
    for (std::size_t k = 0; k < s.size(); ++k) r[k] = f.distance(s[k].p);
    sorted = r;
    auto mid = sorted.begin() + sorted.size() / 2;
    std::nth_element(sorted.begin(), mid, sorted.end());
    f.scale = 1.4826 * *mid;
    const double c = 4.685 * std::max(f.scale, 1e-12);
    for (std::size_t k = 0; k < s.size(); ++k) {
      const double t = r[k] / c;
      w[k] = t < 1 ? (1 - t * t) * (1 - t * t) : 0;
    }
  }
  return f;
}

// Weights 1 for the splats whose normals lie within 25° of the most common direction (the
// candidate, among up to 32 splats spread over the set, that most normals agree with), 0 for
// the others: a start for the plane that the majority face of a leaked surface can win from.
std::vector<double> dominant_direction(std::span<const Sample> s) {
  constexpr double kAgree = 0.906;  // cos 25°
  const std::size_t step = std::max<std::size_t>(1, s.size() / 32);
  std::size_t best = 0, best_count = 0;
  for (std::size_t c = 0; c < s.size(); c += step) {
    std::size_t count = 0;
    for (const Sample& x : s) count += dot(x.n, s[c].n) >= kAgree;
    if (count > best_count) best = c, best_count = count;
  }
  std::vector<double> w(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) w[k] = dot(s[k].n, s[best].n) >= kAgree ? 1 : 0;
  return w;
}

}  // namespace

double SurfacePrimitive::distance(const Vec3d& p) const { return std::abs(signed_distance(p)); }

double SurfacePrimitive::signed_distance(const Vec3d& p) const {
  const Vec3d d = p - point;
  switch (kind) {
    case PrimitiveKind::kPlane:
      return dot(d, direction);
    case PrimitiveKind::kSphere:
      return outward * (norm(d) - radius);
    case PrimitiveKind::kCylinder:
      return outward * (norm(d - direction * dot(d, direction)) - radius);
    case PrimitiveKind::kNone:
      break;
  }
  return kInf;
}

Vec3d SurfacePrimitive::normal_at(const Vec3d& p) const {
  const Vec3d d = p - point;
  Vec3d g;
  switch (kind) {
    case PrimitiveKind::kPlane:
      return direction;
    case PrimitiveKind::kSphere:
      g = d;
      break;
    case PrimitiveKind::kCylinder:
      g = d - direction * dot(d, direction);
      break;
    case PrimitiveKind::kNone:
      return {};
  }
  const double l = norm(g);
  return l > 0 ? g * (outward / l) : Vec3d{};
}

SurfacePrimitive fit_surface_primitive(std::span<const Vec3f> positions,
                                       std::span<const Vec3f> normals,
                                       std::span<const uint32_t> members) {
  if (members.size() < 8) return {};
  Vec3d c;
  for (uint32_t i : members) c += to_vec3d(positions[i]);
  c = c / double(members.size());
  std::vector<Sample> s(members.size());
  for (std::size_t k = 0; k < members.size(); ++k) {
    const uint32_t i = members[k];
    s[k].p = to_vec3d(positions[i]) - c;
    if (finite(normals[i])) s[k].n = to_vec3d(normals[i]);
  }
  constexpr int kIterations = 3;
  const std::vector<double> all(s.size(), 1.0);
  // The plane from all splats, and from those facing the dominant way: a surface that leaked
  // over a crease pulls the first between its faces (reweighting does not get out of it).
  SurfacePrimitive best = fit_robust(s, fit_plane, kIterations, all);
  const SurfacePrimitive majority = fit_robust(s, fit_plane, kIterations, dominant_direction(s));
  if (majority.scale < best.scale) best = majority;
  // A curved model must do clearly better than the plane (a plane is a sphere or cylinder of
  // infinite radius, which the fits approach with large, ill-conditioned radii).
  for (SurfacePrimitive f :
       {fit_robust(s, fit_sphere, kIterations, all), fit_robust(s, fit_cylinder, kIterations, all)})
    if (f.kind != PrimitiveKind::kNone && f.scale < 0.8 * best.scale) best = f;
  best.point += c;
  return best;
}

}  // namespace splatkit::graph
