// The errors of a Sequential Point Tree's disc (spt/spt_disc.h) against values computed by hand
// on small configurations, and the fitted parent's properties.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "spt/spt_disc.h"

namespace splatkit::spt {
namespace {

SptDisc disc(Vec3f c, Vec3f n, float r) {
  SptDisc d;
  d.centre = c;
  d.normal = normalized(n);
  d.radius = r;
  return d;
}

TEST(SptDisc, CoplanarChildrenHaveNoPerpendicularError) {
  const std::vector<SptDisc> kids = {disc({0, 0, 0}, {0, 0, 1}, 1),
                                     disc({1.5f, 0, 0}, {0, 0, 1}, 1),
                                     disc({0.7f, 1.2f, 0}, {0, 0, 1}, 0.5f)};
  const SptDisc p = fit_spt_disc(kids, 0, false);
  EXPECT_NEAR(p.normal.z, 1.0f, 1e-6f);
  EXPECT_NEAR(p.centre.z, 0.0f, 1e-7f);
  EXPECT_NEAR(disc_errors(p, kids).perpendicular, 0.0f, 1e-6f);
}

TEST(SptDisc, ChildTiltedByAKnownAngle) {
  // Two unit discs at the origin, normals z and z tilted by θ about x: the parent's normal is
  // their bisector, each child leans θ/2 from it, d_i = sin(θ/2), so e_p = 2·sin(θ/2).
  for (float theta : {0.1f, 0.5f, 1.0f}) {
    const std::vector<SptDisc> kids = {disc({0, 0, 0}, {0, 0, 1}, 1),
                                       disc({0, 0, 0}, {0, -std::sin(theta), std::cos(theta)}, 1)};
    const SptDisc p = fit_spt_disc(kids, 0, false);
    EXPECT_NEAR(std::acos(dot(p.normal, kids[0].normal)), theta / 2, 1e-4f);
    const DiscErrors e = disc_errors(p, kids);
    EXPECT_NEAR(e.perpendicular, 2 * std::sin(theta / 2), 1e-5f) << theta;
    // The parent (radius 1) reaches beyond the children only across the tilt, by at most
    // 1 − cos(θ/2) (the tilted discs' extent there).
    EXPECT_GE(e.tangential, 0.0f);
    EXPECT_LE(e.tangential, 1 - std::cos(theta / 2) + 1e-5f);
    EXPECT_NEAR(p.error, std::hypot(e.perpendicular, e.tangential), 1e-6f);
  }
}

TEST(SptDisc, OffsetChildAddsItsDistanceToThePerpendicularError) {
  // Parallel discs 0.3 apart along the normal: e_p = 0.3 exactly.
  const std::vector<SptDisc> kids = {disc({0, 0, 0}, {0, 0, 1}, 1),
                                     disc({0, 0, 0.3f}, {0, 0, 1}, 1)};
  EXPECT_NEAR(disc_errors(fit_spt_disc(kids, 0, false), kids).perpendicular, 0.3f, 1e-6f);
}

TEST(SptDisc, ChildrenLeavingPartOfTheParentDiscEmpty) {
  // Two unit discs at x = ±1: the parent (centre 0, radius 2) reaches 1 beyond them along y.
  const std::vector<SptDisc> kids = {disc({-1, 0, 0}, {0, 0, 1}, 1), disc({1, 0, 0}, {0, 0, 1}, 1)};
  const SptDisc p = fit_spt_disc(kids, 0, false);
  EXPECT_NEAR(p.radius, 2.0f, 1e-6f);
  const DiscErrors e = disc_errors(p, kids);
  EXPECT_NEAR(e.perpendicular, 0.0f, 1e-6f);
  EXPECT_NEAR(e.tangential, 1.0f, 1e-5f);
  EXPECT_NEAR(p.error, 1.0f, 1e-5f);
  // A parent of radius 3 over one unit disc at its centre: 2 of its radius is empty everywhere.
  const std::vector<SptDisc> one = {disc({0, 0, 0}, {0, 0, 1}, 1)};
  EXPECT_NEAR(disc_errors(disc({0, 0, 0}, {0, 0, 1}, 3), one).tangential, 2.0f, 1e-6f);
  // A parent that the children fill (the parent is the child): no tangential error.
  EXPECT_NEAR(disc_errors(one[0], one).tangential, 0.0f, 1e-6f);
}

TEST(SptDisc, ParentCoversItsChildrenAndItsErrorIsMonotone) {
  std::vector<SptDisc> kids = {disc({0, 0, 0}, {0, 0.2f, 1}, 0.4f),
                               disc({1, 0.3f, 0.1f}, {0.1f, 0, 1}, 0.6f),
                               disc({0.2f, 1, -0.1f}, {0, 0, 1}, 0.3f)};
  kids[1].error = 5;  // a child with a large error: the parent keeps at least that
  const SptDisc p = fit_spt_disc(kids, 0, false);
  EXPECT_GE(p.error, 5.0f);
  for (const SptDisc& k : kids) {
    const Vec3f v = k.centre - p.centre;
    const Vec3f t = v - p.normal * dot(v, p.normal);
    EXPECT_LE(norm(t) + k.radius, p.radius + 1e-6f);
  }
}

TEST(SptDisc, ColourDeviationRaisesTheError) {
  std::vector<SptDisc> kids = {disc({-1, 0, 0}, {0, 0, 1}, 1), disc({1, 0, 0}, {0, 0, 1}, 1)};
  const float plain = fit_spt_disc(kids, 1, true).error;  // both black
  kids[0].color = {255, 255, 255};
  const SptDisc p = fit_spt_disc(kids, 1, true);
  EXPECT_NEAR(p.color.x, 127.5f, 1e-3f);
  EXPECT_NEAR(p.color_deviation, 0.5f, 1e-6f);
  // e_c = L · 2r · deviation = 1 · 4 · 0.5 = 2; e_t = 1: e_g = √5.
  EXPECT_NEAR(p.error, std::sqrt(5.0f), 1e-5f);
  EXPECT_NEAR(plain, 1.0f, 1e-5f);
  EXPECT_NEAR(fit_spt_disc(kids, 0, true).error, 1.0f, 1e-5f);  // L = 0 ignores colour
}

}  // namespace
}  // namespace splatkit::spt
