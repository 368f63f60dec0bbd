// split_planar_surfaces: a gable standing on a roof plane, joined to it as one surface (as over
// a blended valley), comes off as its two slopes, each on its own plane; a wall and a ledge
// joined in like shares come apart; a noisy plane and a half cylinder stay whole.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/patch_iou.h"
#include "graph/sphere_overlap_graph.h"
#include "graph/split_planar_surfaces.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

constexpr float kSpacing = 0.05f, kRadius = 0.04f;

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<uint32_t> truth;
  void add(Vec3f p, Vec3f n, uint32_t patch) {
    positions.push_back(p);
    normals.push_back(n);
    truth.push_back(patch);
  }
};

// The plane z = 0 over [0, 3]², and on it a gable along y over x in [1, 2], y in [0.5, 2.5]:
// slopes of 40 degrees meeting at a ridge at x = 1.5 (patches 1 and 2), valleys at x = 1 and 2.
// Noise 0.002 along z; exact normals.
Cloud plane_with_gable() {
  Cloud c;
  DeterministicRng rng(3);
  const double slope = std::tan(40 * std::numbers::pi / 180);
  const double cos40 = std::cos(40 * std::numbers::pi / 180),
               sin40 = std::sin(40 * std::numbers::pi / 180);
  for (int a = 0; a <= 60; ++a)
    for (int b = 0; b <= 60; ++b) {
      const double x = kSpacing * a, y = kSpacing * b, e = 0.002 * rng.normal();
      const bool under = x > 1.0 && x < 2.0 && y >= 0.5 && y <= 2.5;
      if (!under) {
        c.add({float(x), float(y), float(e)}, {0, 0, 1}, 0);
        continue;
      }
      // Sampled at the slope's own spacing across: x steps of kSpacing · cos 40 on the gable.
      for (double xs = x; xs < x + kSpacing - 1e-9; xs += kSpacing * cos40) {
        const bool left = xs < 1.5;
        const double z = slope * (0.5 - std::abs(xs - 1.5)) + e;
        c.add({float(xs), float(y), float(z)}, {float(left ? -sin40 : sin40), 0, float(cos40)},
              left ? 1 : 2);
      }
    }
  return c;
}

TEST(GraphSplitPlanarSurfaces, AGableComesOffARoofAsItsTwoSlopes) {
  const Cloud c = plane_with_gable();
  const NeighborGraph g =
      sphere_overlap_graph(c.positions, std::vector<float>(c.positions.size(), kRadius));
  Segmentation one;
  one.surface.assign(c.positions.size(), 0);
  one.sizes = {uint32_t(c.positions.size())};
  uint32_t split = 0;
  const Segmentation out = split_planar_surfaces(
      g, c.positions, c.normals, std::vector<float>(c.positions.size(), kRadius), one, {}, &split);
  EXPECT_EQ(split, 2u);
  ASSERT_EQ(out.count(), 3u);
  for (const PatchMatch& m : patch_iou(c.truth, out.surface))
    EXPECT_GE(m.iou, 0.9) << "patch " << m.patch;

  SplitPlanesOptions none;
  none.offset_scales = 0;
  EXPECT_EQ(split_planar_surfaces(g, c.positions, c.normals,
                                  std::vector<float>(c.positions.size(), kRadius), one, none)
                .count(),
            1u);
}

TEST(GraphSplitPlanarSurfaces, ANoisyPlaneStaysWhole) {
  Cloud c;
  DeterministicRng rng(4);
  for (int a = 0; a < 60; ++a)
    for (int b = 0; b < 60; ++b)
      c.add({kSpacing * float(a), kSpacing * float(b), float(0.01 * rng.normal())},
            {float(0.1 * rng.normal()), float(0.1 * rng.normal()), 1}, 0);
  for (Vec3f& n : c.normals) n = n / std::sqrt(dot(n, n));
  const NeighborGraph g =
      sphere_overlap_graph(c.positions, std::vector<float>(c.positions.size(), kRadius));
  Segmentation one;
  one.surface.assign(c.positions.size(), 0);
  one.sizes = {uint32_t(c.positions.size())};
  uint32_t split = 1;
  const Segmentation out = split_planar_surfaces(
      g, c.positions, c.normals, std::vector<float>(c.positions.size(), kRadius), one, {}, &split);
  EXPECT_EQ(split, 0u);
  EXPECT_EQ(out.surface, one.surface);
}

// One surface made of two faces in like shares: a wall x = 0 (z in [0.05, 1.5]) and a ledge
// z = 0 (x in [0, 1.5]), 30 splats along y; or a half cylinder of radius 1 (axis y), 63 splats
// round. Noise 0.002 across, exact normals.
Cloud wall_and_ledge() {
  Cloud c;
  DeterministicRng rng(6);
  for (int a = 0; a < 30; ++a)
    for (int b = 0; b < 30; ++b) {
      const float e = float(0.002 * rng.normal());
      c.add({kSpacing * float(a), kSpacing * float(b), e}, {0, 0, 1}, 0);
      c.add({e, kSpacing * float(b), kSpacing * float(a + 1)}, {1, 0, 0}, 1);
    }
  return c;
}

Cloud half_cylinder() {
  Cloud c;
  for (int k = 0; k < 63; ++k)
    for (int b = 0; b < 30; ++b) {
      const double t = kSpacing * k;  // 0 .. 3.1 rad
      c.add({float(std::cos(t)), kSpacing * float(b), float(std::sin(t))},
            {float(std::cos(t)), 0, float(std::sin(t))}, 0);
    }
  return c;
}

Segmentation split_whole(const Cloud& c, uint32_t* split) {
  const std::vector<float> radii(c.positions.size(), kRadius);
  const NeighborGraph g = sphere_overlap_graph(c.positions, radii);
  Segmentation one;
  one.surface.assign(c.positions.size(), 0);
  one.sizes = {uint32_t(c.positions.size())};
  return split_planar_surfaces(g, c.positions, c.normals, radii, one, {}, split);
}

TEST(GraphSplitPlanarSurfaces, AWallAndALedgeComeApartAHalfCylinderStaysWhole) {
  const Cloud faces = wall_and_ledge();
  uint32_t split = 0;
  const Segmentation out = split_whole(faces, &split);
  EXPECT_GE(split, 1u);
  for (const PatchMatch& m : patch_iou(faces.truth, out.surface))
    EXPECT_GE(m.iou, 0.95) << "patch " << m.patch;

  const Cloud curved = half_cylinder();
  EXPECT_EQ(split_whole(curved, &split).count(), 1u);
  EXPECT_EQ(split, 0u);
}

}  // namespace
}  // namespace splatkit::graph
