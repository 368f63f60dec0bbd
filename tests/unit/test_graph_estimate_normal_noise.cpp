// estimate_normal_noise: residual of an affine fit of the neighbours' normals — zero for exact
// normals whatever the curvature, the noise's size for perturbed ones.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "graph/build_splat_graph.h"
#include "graph/estimate_normal_noise.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::graph {
namespace {

double noise_of(const SplatCloud& cloud) {
  SplatGraphOptions o;
  o.robust_surfaces = false;
  o.sharp_threshold = -1;  // every edge continuous: the fit sees all neighbours
  const SplatGraph g = build_splat_graph(cloud, o);
  return estimate_normal_noise(g.graph, g.edge_flags, kEdgeSharp, cloud.positions, cloud.normals);
}

TEST(GraphEstimateNormalNoise, ExactNormalsOfCurvedShapesAreNotNoise) {
  for (ShapeKind kind : {ShapeKind::kSphere, ShapeKind::kTorus}) {
    ShapeOptions so;
    so.kind = kind;
    so.points = 20000;
    EXPECT_LT(noise_of(make_shape(so)), 0.3) << shape_kind_name(kind);
  }
}

TEST(GraphEstimateNormalNoise, PerturbedNormalsShowTheirSpread) {
  ShapeOptions so;
  so.kind = ShapeKind::kSphere;
  so.points = 20000;
  SplatCloud cloud = make_shape(so);
  // Each normal tilted by a random 3° (0.052 rad) in a random tangent direction.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> angle(0, 6.2831853f);
  for (Vec3f& n : cloud.normals) {
    const Vec3f t = normalized(cross(n, std::fabs(n.x) < 0.6f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    const Vec3f b = cross(n, t);
    const float a = angle(rng);
    n = normalized(n + (t * std::cos(a) + b * std::sin(a)) * 0.0524f);
  }
  // The residual of a fit with 3 unknowns per coordinate over ~13 neighbours is a little below
  // the spread itself.
  const double noise = noise_of(cloud);
  EXPECT_GT(noise, 2.0);
  EXPECT_LT(noise, 3.5);
}

TEST(GraphEstimateNormalNoise, EmptyAndBadSizes) {
  EXPECT_EQ(estimate_normal_noise(NeighborGraph{}, {}, 1, {}, {}), 0.0);
  NeighborGraph g;
  g.offsets = {0, 0};
  const Vec3f p{0, 0, 0};
  EXPECT_EQ(estimate_normal_noise(g, {}, 1, std::span(&p, 1), std::span(&p, 1)), 0.0);
  EXPECT_THROW(estimate_normal_noise(g, {}, 1, {}, std::span(&p, 1)), std::invalid_argument);
  EXPECT_THROW(estimate_normal_noise(g, {}, 1, std::span(&p, 1), std::span(&p, 1), 0),
               std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
