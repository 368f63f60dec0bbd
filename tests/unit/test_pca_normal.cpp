// pca_normal against matrices built from known eigenpairs: C = R diag(λ) Rᵀ with random rotations,
// including the near-degenerate spectra of real neighbourhoods (flat, nearly flat, line, close
// eigenvalues) and the cases that must not produce NaN.
#include "splatkit/pca_normal.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace splatkit {
namespace {

using Vec = std::array<double, 3>;

struct Rng {
  uint64_t state;
  double uniform() {  // SplitMix64 -> [0, 1)
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
};

// Columns of a random rotation (from a normalised quaternion).
std::array<Vec, 3> random_rotation(Rng& rng) {
  double w = rng.uniform() - 0.5, x = rng.uniform() - 0.5, y = rng.uniform() - 0.5,
         z = rng.uniform() - 0.5;
  double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  return {Vec{1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
          Vec{2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
          Vec{2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)}};
}

// Upper triangle of Σ λ_i e_i e_iᵀ.
std::array<double, 6> compose(const std::array<Vec, 3>& e, const Vec& lambda) {
  std::array<double, 6> c{};
  const int rows[6] = {0, 0, 0, 1, 1, 2}, cols[6] = {0, 1, 2, 1, 2, 2};
  for (int k = 0; k < 6; ++k) {
    for (int i = 0; i < 3; ++i) c[k] += lambda[i] * e[i][rows[k]] * e[i][cols[k]];
  }
  return c;
}

double norm(const Vec& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
double abs_dot(const Vec& a, const Vec& b) {
  return std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}
// Sine of the angle between two unit lines (sign-free), as |a × b|: accurate near 0.
double line_error(const Vec& a, const Vec& b) {
  return norm({a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]});
}

void expect_orthonormal(const CovarianceEigen& r) {
  EXPECT_NEAR(norm(r.normal), 1.0, 1e-14);
  EXPECT_NEAR(norm(r.axis), 1.0, 1e-14);
  EXPECT_LT(abs_dot(r.normal, r.axis), 1e-13);
  EXPECT_LE(r.eigenvalues[0], r.eigenvalues[1]);
  EXPECT_LE(r.eigenvalues[1], r.eigenvalues[2]);
  EXPECT_GE(r.eigenvalues[0], 0.0);
}

// Checks normal (and axis, when its eigenvalue is simple) against the construction, over many
// random rotations. tolerance: sine of the angle.
void check_spectrum(const Vec& lambda, double normal_tolerance, double axis_tolerance,
                    uint64_t seed) {
  Rng rng{seed};
  for (int trial = 0; trial < 2000; ++trial) {
    auto e = random_rotation(rng);
    CovarianceEigen r = pca_normal(compose(e, lambda));
    expect_orthonormal(r);
    ASSERT_LT(line_error(r.normal, e[0]), normal_tolerance) << "trial " << trial;
    ASSERT_LT(line_error(r.axis, e[2]), axis_tolerance) << "trial " << trial;
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(r.eigenvalues[i], lambda[i], 1e-13 * lambda[2]);
  }
}

TEST(PcaNormal, DiagonalMatrix) {
  CovarianceEigen r = pca_normal({3, 0, 0, 2, 0, 1});
  EXPECT_DOUBLE_EQ(r.eigenvalues[0], 1);
  EXPECT_DOUBLE_EQ(r.eigenvalues[1], 2);
  EXPECT_DOUBLE_EQ(r.eigenvalues[2], 3);
  EXPECT_NEAR(abs_dot(r.normal, {0, 0, 1}), 1.0, 1e-15);
  EXPECT_NEAR(abs_dot(r.axis, {1, 0, 0}), 1.0, 1e-15);
}

TEST(PcaNormal, GenericSpectrum) { check_spectrum({0.3, 0.5, 0.9}, 1e-13, 1e-13, 1); }

TEST(PcaNormal, ExactPlane) { check_spectrum({0.0, 1.0, 1.0}, 1e-14, 1.0, 2); }

TEST(PcaNormal, NearlyFlatWithNoise) {
  check_spectrum({1e-12, 0.5, 1.0}, 1e-13, 1e-13, 3);
  check_spectrum({1e-6, 0.9, 1.0}, 1e-13, 1e-11, 4);
}

TEST(PcaNormal, CloseSmallestEigenvalues) {
  // An ill-conditioned normal: the error may grow like eps / gap, no more.
  check_spectrum({1.0, 1.0 + 1e-6, 2.0}, 1e-8, 1e-13, 5);
}

TEST(PcaNormal, LineGivesExactAxisAndSomePerpendicular) {
  Rng rng{6};
  for (int trial = 0; trial < 2000; ++trial) {
    auto e = random_rotation(rng);
    for (const Vec& lambda : {Vec{0, 0, 1}, Vec{1e-9, 1e-9, 1}, Vec{1e-9, 2e-9, 1}}) {
      CovarianceEigen r = pca_normal(compose(e, lambda));
      expect_orthonormal(r);
      ASSERT_LT(line_error(r.axis, e[2]), 1e-13);
      ASSERT_LT(abs_dot(r.normal, e[2]), 1e-13);
      ASSERT_LE(r.eigenvalues[1], 3e-9);
    }
  }
}

TEST(PcaNormal, ScaleInvariantOverTheDoubleRange) {
  Rng rng{7};
  auto e = random_rotation(rng);
  const Vec lambda = {1e-4, 0.5, 1.0};
  for (double s : {1e-300, 1e-150, 1.0, 1e150, 1e300}) {
    CovarianceEigen r = pca_normal(compose(e, {lambda[0] * s, lambda[1] * s, lambda[2] * s}));
    expect_orthonormal(r);
    EXPECT_LT(line_error(r.normal, e[0]), 1e-12) << s;
    EXPECT_NEAR(r.eigenvalues[2], s, 1e-12 * s) << s;
  }
}

TEST(PcaNormal, PlaneFromPoints) {
  // Points on z = 0.3 x + 0.2 y: normal ∝ (-0.3, -0.2, 1), smallest eigenvalue 0.
  std::array<double, 6> c{};
  double mean[3] = {0, 0, 0};
  const int n = 25;
  Vec pts[n];
  for (int i = 0; i < n; ++i) {
    double x = i % 5 - 2.0, y = i / 5 - 2.0;
    pts[i] = {x, y, 0.3 * x + 0.2 * y};
    for (int a = 0; a < 3; ++a) mean[a] += pts[i][a] / n;
  }
  for (const Vec& p : pts) {
    double d[3] = {p[0] - mean[0], p[1] - mean[1], p[2] - mean[2]};
    c[0] += d[0] * d[0], c[1] += d[0] * d[1], c[2] += d[0] * d[2];
    c[3] += d[1] * d[1], c[4] += d[1] * d[2], c[5] += d[2] * d[2];
  }
  CovarianceEigen r = pca_normal(c);
  const double len = std::sqrt(0.09 + 0.04 + 1.0);
  EXPECT_NEAR(abs_dot(r.normal, {-0.3 / len, -0.2 / len, 1 / len}), 1.0, 1e-14);
  EXPECT_NEAR(r.eigenvalues[0], 0.0, 1e-13);
}

TEST(PcaNormal, DegenerateAndInvalidInputNeverGiveNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const std::array<double, 6>& c : {std::array<double, 6>{0, 0, 0, 0, 0, 0},
                                         {7, 0, 0, 7, 0, 7},
                                         {nan, 0, 0, 1, 0, 1},
                                         {1, inf, 0, 1, 0, 1},
                                         {1e-320, 0, 0, 1e-320, 0, 1e-320},
                                         {1, 1, 1, 1, 1, 1}}) {
    CovarianceEigen r = pca_normal(c);
    expect_orthonormal(r);
    for (double x : r.eigenvalues) EXPECT_TRUE(std::isfinite(x));
  }
  CovarianceEigen iso = pca_normal({7, 0, 0, 7, 0, 7});
  EXPECT_EQ(iso.eigenvalues, (std::array<double, 3>{7, 7, 7}));
  EXPECT_EQ(iso.normal, (Vec{0, 0, 1}));
  CovarianceEigen bad = pca_normal({nan, 0, 0, 1, 0, 1});
  EXPECT_EQ(bad.eigenvalues, (std::array<double, 3>{0, 0, 0}));
  // All ones: rank 1 with axis (1, 1, 1) / √3.
  CovarianceEigen ones = pca_normal({1, 1, 1, 1, 1, 1});
  EXPECT_NEAR(abs_dot(ones.axis, {1 / std::sqrt(3.0), 1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}), 1.0,
              1e-14);
  EXPECT_NEAR(ones.eigenvalues[2], 3.0, 1e-14);
}

}  // namespace
}  // namespace splatkit
