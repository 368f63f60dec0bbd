#include "splatkit/pca_normal.h"

#include <algorithm>
#include <cmath>

namespace splatkit {

namespace {

using Vec = std::array<double, 3>;
using Matrix = std::array<Vec, 3>;

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec times(const Matrix& m, const Vec& v) { return {dot(m[0], v), dot(m[1], v), dot(m[2], v)}; }

// Unit eigenvector of a simple eigenvalue `lambda`: orthogonal to every row of M − λI, which has
// rank 2, so the longest cross product of two rows is the best-conditioned choice.
Vec null_vector(const Matrix& m, double lambda) {
  const Vec r0 = {m[0][0] - lambda, m[0][1], m[0][2]};
  const Vec r1 = {m[1][0], m[1][1] - lambda, m[1][2]};
  const Vec r2 = {m[2][0], m[2][1], m[2][2] - lambda};
  Vec best = cross(r0, r1);
  double best_norm2 = dot(best, best);
  for (const Vec& c : {cross(r0, r2), cross(r1, r2)}) {
    double n2 = dot(c, c);
    if (n2 > best_norm2) {
      best = c;
      best_norm2 = n2;
    }
  }
  if (!(best_norm2 > 0)) return {0, 0, 1};  // only for an exactly isotropic matrix
  const double inv = 1.0 / std::sqrt(best_norm2);
  return {best[0] * inv, best[1] * inv, best[2] * inv};
}

// u, v such that (w, u, v) is orthonormal, for a unit w (the larger of two components keeps the
// square root away from zero).
void complete_basis(const Vec& w, Vec& u, Vec& v) {
  if (std::abs(w[0]) > std::abs(w[1])) {
    const double inv = 1.0 / std::sqrt(w[0] * w[0] + w[2] * w[2]);
    u = {-w[2] * inv, 0, w[0] * inv};
  } else {
    const double inv = 1.0 / std::sqrt(w[1] * w[1] + w[2] * w[2]);
    u = {0, w[2] * inv, -w[1] * inv};
  }
  v = cross(w, u);
}

// The eigenvalues of m, ascending, from the trigonometric solution of the characteristic cubic.
// Returns false when m is a multiple of the identity (all three equal).
bool eigenvalues(const Matrix& m, Vec& values) {
  const double q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
  const double b00 = m[0][0] - q, b11 = m[1][1] - q, b22 = m[2][2] - q;
  const double off2 = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
  const double p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * off2;
  if (!(p2 > 0)) {
    values = {q, q, q};
    return false;
  }
  const double p = std::sqrt(p2 / 6.0);
  const double det = b00 * (b11 * b22 - m[1][2] * m[1][2]) -
                     m[0][1] * (m[0][1] * b22 - m[1][2] * m[0][2]) +
                     m[0][2] * (m[0][1] * m[1][2] - b11 * m[0][2]);
  const double r = std::clamp(det / (2.0 * p * p * p), -1.0, 1.0);
  // phi in [0, π/3]; cos(phi + 2π/3) = −cos(phi)/2 − (√3/2) sin(phi) saves a second cosine.
  const double phi = std::acos(r) / 3.0;
  const double cos_phi = std::cos(phi), sin_phi = std::sqrt(std::max(0.0, 1.0 - cos_phi * cos_phi));
  const double largest = q + 2.0 * p * cos_phi;
  const double smallest = q + 2.0 * p * (-0.5 * cos_phi - 0.86602540378443864676 * sin_phi);
  const double middle = std::clamp(3.0 * q - smallest - largest, smallest, largest);
  values = {smallest, middle, largest};
  return true;
}

}  // namespace

CovarianceEigen pca_normal(const std::array<double, 6>& c) {
  CovarianceEigen out;
  double scale = 0;
  for (double x : c) {
    if (!std::isfinite(x)) return out;
    scale = std::max(scale, std::abs(x));
  }
  if (scale == 0) return out;
  // Scaled to entries in [-1, 1]: the cubic's powers can neither overflow nor underflow. (Divided,
  // not multiplied by 1 / scale, which overflows for a subnormal scale.)
  const Matrix m = {Vec{c[0] / scale, c[1] / scale, c[2] / scale},
                    Vec{c[1] / scale, c[3] / scale, c[4] / scale},
                    Vec{c[2] / scale, c[4] / scale, c[5] / scale}};
  Vec values;
  if (!eigenvalues(m, values)) {
    out.eigenvalues.fill(std::max(values[0] * scale, 0.0));
    return out;
  }

  // The extreme eigenvalue farther from the middle one has a well-conditioned eigenvector; the
  // other two solve the exact 2×2 problem [[m00, m01], [m01, m11]] in its orthogonal plane.
  const bool normal_first = values[1] - values[0] >= values[2] - values[1];
  const Vec w = null_vector(m, normal_first ? values[0] : values[2]);
  Vec u, v;
  complete_basis(w, u, v);
  const Vec mu = times(m, u), mv = times(m, v);
  const double m00 = dot(u, mu), m01 = dot(u, mv), m11 = dot(v, mv);
  const double half_sum = 0.5 * (m00 + m11), half_diff = 0.5 * (m00 - m11);
  const double radius = std::sqrt(half_diff * half_diff + m01 * m01);
  // Eigenvector (in u, v coordinates) of the 2×2's larger eigenvalue: (radius + half_diff, m01)
  // or (m01, radius − half_diff), whichever is longer (they are parallel; the longer one has no
  // cancellation). Both vanish only for a double root, where any direction is right.
  double a = radius + half_diff, b = m01;
  if (half_diff < 0) a = m01, b = radius - half_diff;
  double len = std::sqrt(a * a + b * b);
  if (len > 0) {
    a /= len, b /= len;
  } else {
    a = 1, b = 0;
  }
  const Vec larger = {a * u[0] + b * v[0], a * u[1] + b * v[1], a * u[2] + b * v[2]};
  const Vec smaller = {-b * u[0] + a * v[0], -b * u[1] + a * v[1], -b * u[2] + a * v[2]};
  out.normal = normal_first ? w : smaller;
  out.axis = normal_first ? larger : w;

  // The cubic's roots lose half the digits at a double root (the acos near ±1); the Rayleigh
  // quotients of the accurate vectors do not, and any vector of a double root gives its value.
  const double w_value = dot(w, times(m, w));
  Vec refined = normal_first ? Vec{w_value, half_sum - radius, half_sum + radius}
                             : Vec{half_sum - radius, half_sum + radius, w_value};
  std::sort(refined.begin(), refined.end());
  for (int i = 0; i < 3; ++i) out.eigenvalues[i] = std::max(refined[i] * scale, 0.0);
  return out;
}

}  // namespace splatkit
