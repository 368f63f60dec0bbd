// fit_surface_primitive: planes, spheres and cylinders recovered exactly from exact samples,
// closely from noisy ones, and despite a minority of splats from another surface.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

#include "graph/fit_surface_primitive.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

constexpr double kPi = std::numbers::pi;

struct Samples {
  std::vector<Vec3f> positions, normals;
  std::vector<uint32_t> all() const {
    std::vector<uint32_t> m(positions.size());
    std::iota(m.begin(), m.end(), 0u);
    return m;
  }
  void add(const Vec3d& p, const Vec3d& n) {
    positions.push_back({float(p.x), float(p.y), float(p.z)});
    normals.push_back({float(n.x), float(n.y), float(n.z)});
  }
};

// A patch of the plane z = 0.5 tilted about x by 30°, 40 × 40 samples; noise along the normal.
Samples tilted_plane(double noise, uint64_t seed = 1) {
  DeterministicRng rng(seed);
  const Vec3d n{0, -std::sin(kPi / 6), std::cos(kPi / 6)}, u{1, 0, 0}, v = cross(n, u);
  Samples s;
  for (int a = 0; a < 40; ++a)
    for (int b = 0; b < 40; ++b)
      s.add(Vec3d{0, 0, 0.5} + u * (a * 0.05) + v * (b * 0.05) + n * (noise * rng.normal()), n);
  return s;
}

// A band of the cylinder of radius r about the axis through c along a (unit), normals outward
// (sign +1) or inward (-1).
Samples cylinder(const Vec3d& c, const Vec3d& a, double r, double sign, double noise) {
  DeterministicRng rng(2);
  const Vec3d u = cross(a, Vec3d{0, 0, 1}) / norm(cross(a, Vec3d{0, 0, 1})), v = cross(a, u);
  Samples s;
  for (int k = 0; k < 60; ++k)
    for (int h = 0; h < 20; ++h) {
      const double t = 2 * kPi * k / 60;
      const Vec3d radial = u * std::cos(t) + v * std::sin(t);
      s.add(c + a * (h * 0.05) + radial * (r + noise * rng.normal()), radial * sign);
    }
  return s;
}

TEST(GraphFitSurfacePrimitive, ExactPlane) {
  const Samples s = tilted_plane(0);
  const SurfacePrimitive f = fit_surface_primitive(s.positions, s.normals, s.all());
  ASSERT_EQ(f.kind, PrimitiveKind::kPlane);
  EXPECT_NEAR(f.direction.y, -0.5, 1e-6);
  EXPECT_NEAR(f.direction.z, std::sqrt(0.75), 1e-6);
  EXPECT_LT(f.scale, 1e-6);
  // Signed: positive on the normals' side; the normal is the plane's everywhere.
  EXPECT_NEAR(f.signed_distance(Vec3d{0, 0, 0.5} + f.direction * 0.25), 0.25, 1e-6);
  EXPECT_NEAR(f.signed_distance(Vec3d{0.3, 0, 0.5} - f.direction * 0.1), -0.1, 1e-6);
  EXPECT_NEAR(f.distance(Vec3d{0.3, 0, 0.5} - f.direction * 0.1), 0.1, 1e-6);
  EXPECT_NEAR(dot(f.normal_at({5, 5, 5}), f.direction), 1, 1e-12);
}

TEST(GraphFitSurfacePrimitive, NoisyPlaneWithAnotherFaceLeakedIn) {
  Samples s = tilted_plane(0.01);
  // 5 % of the splats from a face at 90° (a border band that went to the wrong surface).
  for (int k = 0; k < 80; ++k) s.add({0.02 * (k % 10), 0.1 * (k / 10), 1.5}, {0, 1, 0});
  const SurfacePrimitive f = fit_surface_primitive(s.positions, s.normals, s.all());
  ASSERT_EQ(f.kind, PrimitiveKind::kPlane);
  EXPECT_NEAR(f.direction.y, -0.5, 0.01);
  EXPECT_NEAR(f.signed_distance({0, 0, 0.5}), 0, 0.002);
  EXPECT_NEAR(f.scale, 0.01, 0.0015);  // the noise, not the leak
}

TEST(GraphFitSurfacePrimitive, TwoFacesFollowTheLargerOne) {
  // A third of the splats from a face at 90° (two faces that leaked into one surface): the
  // least-squares plane lies between them and reweighting alone stays there; the start from
  // the dominant normal direction finds the larger face.
  Samples s = tilted_plane(0.01);
  const Vec3d n{0, -std::sin(kPi / 6), std::cos(kPi / 6)}, u{1, 0, 0}, v = cross(n, u);
  for (int a = 0; a < 40; ++a)
    for (int b = 1; b <= 20; ++b) s.add(Vec3d{0, 0, 0.5} + u * (a * 0.05) - n * (b * 0.05), -v);
  const SurfacePrimitive f = fit_surface_primitive(s.positions, s.normals, s.all());
  ASSERT_EQ(f.kind, PrimitiveKind::kPlane);
  EXPECT_NEAR(dot(f.direction, n), 1, 1e-3);
  EXPECT_NEAR(f.signed_distance({0, 0, 0.5}), 0, 0.003);
}

TEST(GraphFitSurfacePrimitive, SphereOutwardAndInward) {
  DeterministicRng rng(3);
  const Vec3d c{1, 2, 3};
  Samples out, in;
  for (int k = 0; k < 2000; ++k) {
    // A cap of 60° around +z, where a plane would not do.
    const double z = 1 - 0.5 * rng.uniform(), phi = 2 * kPi * rng.uniform();
    const double rho = std::sqrt(1 - z * z);
    const Vec3d d{rho * std::cos(phi), rho * std::sin(phi), z};
    out.add(c + d * 2, d);
    in.add(c + d * 2, -d);
  }
  for (const Samples* s : {&out, &in}) {
    const SurfacePrimitive f = fit_surface_primitive(s->positions, s->normals, s->all());
    ASSERT_EQ(f.kind, PrimitiveKind::kSphere);
    EXPECT_NEAR(f.radius, 2, 1e-5);
    EXPECT_NEAR(norm(f.point - c), 0, 1e-5);
    EXPECT_EQ(f.outward, s == &out ? 1 : -1);
    EXPECT_NEAR(f.signed_distance(c + Vec3d{0, 0, 2.5}), s == &out ? 0.5 : -0.5, 1e-5);
    EXPECT_NEAR(f.normal_at(c + Vec3d{0, 0, 7}).z, f.outward, 1e-9);
  }
}

TEST(GraphFitSurfacePrimitive, CylinderOfAHole) {
  const Vec3d axis = Vec3d{1, 1, 1} / std::sqrt(3.0), c{0.5, -0.2, 0.1};
  const Samples exact = cylinder(c, axis, 0.25, -1, 0);
  SurfacePrimitive f = fit_surface_primitive(exact.positions, exact.normals, exact.all());
  ASSERT_EQ(f.kind, PrimitiveKind::kCylinder);
  EXPECT_NEAR(f.radius, 0.25, 1e-5);
  EXPECT_NEAR(std::abs(dot(f.direction, axis)), 1, 1e-9);
  EXPECT_EQ(f.outward, -1);  // normals point to the axis
  // A point on the axis is 0.25 inside-out: on the side the normals point to.
  EXPECT_NEAR(f.signed_distance(c + axis * 0.3), 0.25, 1e-5);

  const Samples noisy = cylinder(c, axis, 0.25, 1, 0.002);
  f = fit_surface_primitive(noisy.positions, noisy.normals, noisy.all());
  ASSERT_EQ(f.kind, PrimitiveKind::kCylinder);
  EXPECT_NEAR(f.radius, 0.25, 0.001);
  EXPECT_EQ(f.outward, 1);
  EXPECT_NEAR(f.scale, 0.002, 0.0005);
}

TEST(GraphFitSurfacePrimitive, TooFewSplats) {
  const Samples s = tilted_plane(0);
  const std::vector<uint32_t> seven{0, 1, 2, 40, 41, 42, 80};
  const SurfacePrimitive f = fit_surface_primitive(s.positions, s.normals, seven);
  EXPECT_EQ(f.kind, PrimitiveKind::kNone);
  EXPECT_EQ(f.distance({0, 0, 0}), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace splatkit::graph
