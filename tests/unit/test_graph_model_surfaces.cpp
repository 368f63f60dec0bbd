// model_surfaces: islands of one cylinder join the largest; a surface made of two faces splits
// into them; a free-form surface stays whole and unexplained; small surfaces get no model.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/model_surfaces.h"
#include "graph/sphere_overlap_graph.h"
#include "graph/surface_borders.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

struct Cloud {
  std::vector<Vec3f> positions, normals;
  NeighborGraph graph;
  void connect(float radius) {
    graph = sphere_overlap_graph(positions, std::vector<float>(positions.size(), radius));
  }
};

// The inside of a hole: radius 1 about the z axis, 120 splats around × 10 up (spacing ≈ 0.052),
// normals to the axis, noise 0.002 along them.
Cloud hole() {
  Cloud c;
  DeterministicRng rng(5);
  for (int h = 0; h < 10; ++h)
    for (int k = 0; k < 120; ++k) {
      const double t = 2 * std::numbers::pi * k / 120, r = 1 + 0.002 * rng.normal();
      c.positions.push_back({float(r * std::cos(t)), float(r * std::sin(t)), float(0.05 * h)});
      c.normals.push_back({float(-std::cos(t)), float(-std::sin(t)), 0});
    }
  c.connect(0.04f);
  return c;
}

TEST(GraphModelSurfaces, IslandsOfOneCylinderJoinTheLargest) {
  Cloud c = hole();
  // Arcs of 60, 40 and 20 splats around (600, 400 and 200 splats), labels 2, 0, 1.
  std::vector<uint32_t> label(c.positions.size());
  for (std::size_t i = 0; i < label.size(); ++i) {
    const std::size_t k = i % 120;
    label[i] = k < 60 ? 2 : (k < 100 ? 0 : 1);
  }
  uint32_t count = 3;
  SurfaceBorders b = surface_borders(c.graph, label);
  const SurfaceModels m =
      model_surfaces(c.graph, c.positions, c.normals, label, count, b, 50, -0.5f);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(m.joined, 2u);
  EXPECT_EQ(m.split, 0u);
  EXPECT_EQ(label, std::vector<uint32_t>(label.size(), 2));
  ASSERT_EQ(m.model[2].state, SurfaceModel::kPrimitive);
  EXPECT_EQ(m.model[2].primitive.kind, PrimitiveKind::kCylinder);
  EXPECT_NEAR(m.model[2].primitive.radius, 1, 0.002);
  EXPECT_EQ(m.model[2].primitive.outward, -1);
  EXPECT_EQ(m.model[0].state, SurfaceModel::kFragment);  // joined: no model, no splat
  EXPECT_TRUE(b.splats.empty());
  EXPECT_TRUE(b.pairs.empty());
}

TEST(GraphModelSurfaces, TwoFacesInOneSurfaceSplit) {
  // z = 0 for x in (0, 20) and x = 0 for z in (-12, 0), y in [-10, 10), spacing 1: one label.
  Cloud c;
  for (int a = 0; a < 20; ++a)
    for (int b = -10; b < 10; ++b) {
      c.positions.push_back({a + 0.5f, float(b), 0});
      c.normals.push_back({0, 0, 1});
    }
  for (int a = 0; a < 12; ++a)
    for (int b = -10; b < 10; ++b) {
      c.positions.push_back({0, float(b), -a - 0.5f});
      c.normals.push_back({-1, 0, 0});
    }
  c.connect(0.75f);
  std::vector<uint32_t> label(c.positions.size(), 0);
  uint32_t count = 1;
  SurfaceBorders b = surface_borders(c.graph, label);
  const SurfaceModels m =
      model_surfaces(c.graph, c.positions, c.normals, label, count, b, 50, -0.5f);
  EXPECT_EQ(m.split, 1u);
  ASSERT_EQ(count, 2u);
  for (std::size_t i = 0; i < label.size(); ++i) EXPECT_EQ(label[i], i < 400 ? 0u : 1u) << i;
  for (uint32_t s : {0u, 1u}) {
    ASSERT_EQ(m.model[s].state, SurfaceModel::kPrimitive);
    EXPECT_EQ(m.model[s].primitive.kind, PrimitiveKind::kPlane);
  }
  EXPECT_EQ(b.pairs, (std::vector<uint64_t>{1, uint64_t{1} << 32}));
}

TEST(GraphModelSurfaces, FreeFormStaysWholeAndSmallGetsNoModel) {
  // A bumpy sheet z = 0.4 sin(x / 2) sin(y / 2), 30 × 30, and a 5 × 5 patch of it labelled apart.
  Cloud c;
  for (int a = 0; a < 30; ++a)
    for (int b = 0; b < 30; ++b) {
      const float x = float(a), y = float(b);
      c.positions.push_back({x, y, 0.4f * std::sin(x / 2) * std::sin(y / 2)});
      c.normals.push_back(normalized(Vec3f{-0.2f * std::cos(x / 2) * std::sin(y / 2),
                                           -0.2f * std::sin(x / 2) * std::cos(y / 2), 1}));
    }
  c.connect(0.75f);
  std::vector<uint32_t> label(c.positions.size(), 0);
  for (int a = 10; a < 15; ++a)
    for (int b = 10; b < 15; ++b) label[a * 30 + b] = 1;
  const std::vector<uint32_t> before = label;
  uint32_t count = 2;
  SurfaceBorders b = surface_borders(c.graph, label);
  const SurfaceModels m =
      model_surfaces(c.graph, c.positions, c.normals, label, count, b, 50, -0.5f);
  EXPECT_EQ(label, before);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(m.model[0].state, SurfaceModel::kUnexplained);
  EXPECT_EQ(m.model[1].state, SurfaceModel::kFragment);
  EXPECT_EQ(b.splats.size(), 16u + 24u);  // the patch's outer ring, the ring around it
}

}  // namespace
}  // namespace splatkit::graph
