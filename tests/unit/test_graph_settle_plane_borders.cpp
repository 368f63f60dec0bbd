// settle_plane_borders: a band of a gable slope that the segmentation left with the roof it
// stands on (as over a blended valley) goes back to the slope, the roof keeps every splat on its
// plane; planes nearer parallel than the crease angle (a relief step) and offset_scales 0 change
// nothing; one thread or many give the same ids.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/settle_plane_borders.h"
#include "graph/sphere_overlap_graph.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

constexpr float kSpacing = 0.05f, kRadius = 0.04f;

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<float> radii;
  std::vector<uint32_t> truth, label;
  Segmentation segmentation() const {
    Segmentation s;
    s.surface = label;
    s.sizes.assign(2, 0);
    for (uint32_t l : label) ++s.sizes[l];
    return s;
  }
};

// The roof z = 0 for x in [0, 2] (patch 0) and a slope rising at `degrees` from x = 2 (patch 1),
// both 2 m along y; noise 0.002 along each plane's normal, exact normals. The slope's first
// `band` rows beyond the crease are labelled as the roof.
Cloud roof_and_slope(double degrees, int band) {
  Cloud c;
  DeterministicRng rng(5);
  const double t = degrees * std::numbers::pi / 180;
  const Vec3f up{0, 0, 1}, slope_n{float(-std::sin(t)), 0, float(std::cos(t))};
  for (int b = 0; b <= 40; ++b) {
    const float y = kSpacing * float(b);
    for (int a = 0; a <= 40; ++a) {
      const float e = float(0.002 * rng.normal());
      c.positions.push_back({kSpacing * float(a), y, e});
      c.normals.push_back(up);
      c.truth.push_back(0);
      c.label.push_back(0);
    }
    for (int a = 1; a <= 30; ++a) {
      const double s = kSpacing * a, e = 0.002 * rng.normal();
      c.positions.push_back({float(2 + s * std::cos(t) - e * std::sin(t)), y,
                             float(s * std::sin(t) + e * std::cos(t))});
      c.normals.push_back(slope_n);
      c.truth.push_back(1);
      c.label.push_back(a <= band ? 0 : 1);
    }
  }
  c.radii.assign(c.positions.size(), kRadius);
  return c;
}

// Expects every splat on its true face (ids by lowest splat: splat 0 is on the roof) except the
// roof's last column (x = 2), which lies on the crease, on both planes: either face may take
// it. Returns how many of those the slope took.
uint32_t expect_true_faces(const Segmentation& out, const Cloud& c) {
  uint32_t on_crease_moved = 0;
  for (std::size_t i = 0; i < c.truth.size(); ++i) {
    if (c.positions[i].x == 2.0f) {
      on_crease_moved += out.surface[i] != 0;
      continue;
    }
    EXPECT_EQ(out.surface[i], c.truth[i]) << i;
  }
  return on_crease_moved;
}

TEST(GraphSettlePlaneBorders, ABandOfTheSlopeGoesBackToIt) {
  const Cloud c = roof_and_slope(40, 3);
  const NeighborGraph g = sphere_overlap_graph(c.positions, c.radii);
  uint64_t moved = 0;
  const Segmentation out =
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), {}, &moved);
  ASSERT_EQ(out.count(), 2u);
  EXPECT_EQ(moved, 3u * 41u + expect_true_faces(out, c));

  SettlePlaneBordersOptions none;
  none.offset_scales = 0;
  EXPECT_EQ(
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), none).surface,
      c.label);
}

TEST(GraphSettlePlaneBorders, PlanesNearerParallelThanTheCreaseAngleStay) {
  // 20 degrees: within min_crease_degrees (30), as the tilted pieces of a facade's relief.
  const Cloud c = roof_and_slope(20, 3);
  const NeighborGraph g = sphere_overlap_graph(c.positions, c.radii);
  uint64_t moved = 1;
  const Segmentation out =
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), {}, &moved);
  EXPECT_EQ(out.surface, c.label);
  EXPECT_EQ(moved, 0u);

  SettlePlaneBordersOptions wider;
  wider.min_crease_degrees = 10;
  const Segmentation settled =
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), wider);
  expect_true_faces(settled, c);
}

TEST(GraphSettlePlaneBorders, SameIdsOnOneThreadOrMany) {
  const Cloud c = roof_and_slope(40, 4);
  const NeighborGraph g = sphere_overlap_graph(c.positions, c.radii);
  const Segmentation many =
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), {});
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Segmentation single =
      settle_plane_borders(g, c.positions, c.normals, c.radii, c.segmentation(), {});
  EXPECT_EQ(single.surface, many.surface);
  EXPECT_EQ(single.sizes, many.sizes);
}

}  // namespace
}  // namespace splatkit::graph
