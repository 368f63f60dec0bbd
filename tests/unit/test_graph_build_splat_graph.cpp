// build_splat_graph on synthetic planes with known creases: one sharp line, two surfaces.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <vector>

#include "graph/build_splat_graph.h"
#include "graph/make_clip_planes.h"
#include "splatkit/error.h"

namespace splatkit::graph {
namespace {

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<float> radii;
  float radius = 0.75f;  // grid step 1: the 8-neighbourhood overlaps (sqrt 2 < 1.5)
  void add(const Vec3f& p, const Vec3f& n) {
    positions.push_back(p);
    normals.push_back(n);
    radii.push_back(radius);
  }
};

// A 10 × 10 grid of unit spacing in a plane through `origin` spanned by a and b, at
// origin + (i + 0.5) a + (j + 0.5) b: exact coordinates in float.
void add_grid(Cloud& c, const Vec3f& origin, const Vec3f& a, const Vec3f& b, const Vec3f& n,
              int rows = 10) {
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < rows; ++i) c.add(origin + a * (i + 0.5f) + b * (j + 0.5f), n);
}

// Floor z = 0 (x > 0) and wall x = 0 (z > 0) meet at 90° along the y axis: a concave crease.
Cloud floor_and_wall(float radius = 0.75f) {
  Cloud c;
  c.radius = radius;
  add_grid(c, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});  // splats 0..99, x = i + 0.5
  add_grid(c, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0});  // splats 100..199, z = i + 0.5
  return c;
}

SplatGraph build(const Cloud& c, SplatGraphOptions o = {}) {
  return build_splat_graph(c.positions, c.normals, c.radii, o);
}

bool discards(const SplatGraph& g, const Cloud& c, std::size_t splat, const Vec3f& p) {
  const auto planes = make_clip_planes(g.clip, c.positions, c.normals);
  return fragment_discarded(clip_view(g.clip, planes, splat), p);
}

TEST(GraphBuildSplatGraph, TwoPlanesAt90DegreesGiveOneSharpLineAndTwoSurfaces) {
  const Cloud c = floor_and_wall();
  const SplatGraph g = build(c);
  EXPECT_NO_THROW(g.clip.check_consistent());
  // Sharp edges join only the floor column x = 0.5 and the wall row z = 0.5, |Δy| <= 1
  // (distance² 0.5 + Δy² < 1.5²): 10 + 2 · 9 pairs, and all of them cross.
  EXPECT_EQ(g.stats.sharp_edges, 28u);
  EXPECT_EQ(g.stats.crossing_edges, 28u);
  // Each grid: 9 · 10 · 2 axis pairs + 9 · 9 · 2 diagonals = 342; plus the 28 sharp ones.
  EXPECT_EQ(g.stats.edges, 2 * 342u + 28u);
  ASSERT_EQ(g.surfaces.count(), 2u);
  EXPECT_EQ(g.surfaces.sizes, (std::vector<uint32_t>{100, 100}));
  for (std::size_t i = 0; i < 200; ++i) {
    const bool on_crease = (i < 100 ? c.positions[i].x : c.positions[i].z) == 0.5f;
    EXPECT_EQ(g.surfaces.surface[i], i < 100 ? 0u : 1u);
    EXPECT_EQ(g.classes[i], on_crease ? SplatClass::kEdge : SplatClass::kSmooth) << i;
    EXPECT_EQ(g.clip.offsets[i + 1] > g.clip.offsets[i], on_crease) << i;
  }
  EXPECT_EQ(g.stats.candidate_splats, 20u);
  EXPECT_EQ(g.stats.clipped_splats, 20u);
  // Floor splat (0.5, 4.5, 0): partners are the wall splats at y = 3.5, 4.5, 5.5.
  const std::size_t floor_splat = 40;
  ASSERT_EQ(c.positions[floor_splat], (Vec3f{0.5f, 4.5f, 0}));
  const auto row = std::span(g.clip.partners).subspan(g.clip.offsets[floor_splat], 3);
  EXPECT_EQ(std::vector<uint32_t>(row.begin(), row.end()), (std::vector<uint32_t>{130, 140, 150}));
  // Concave crease: what lies behind the wall (x < 0) goes, the floor stays; likewise below
  // the floor for a wall splat.
  EXPECT_TRUE(discards(g, c, floor_splat, {-0.25f, 4.5f, 0}));
  EXPECT_FALSE(discards(g, c, floor_splat, {0.25f, 4.5f, 0}));
  EXPECT_TRUE(discards(g, c, 140, {0, 4.5f, -0.25f}));
  EXPECT_FALSE(discards(g, c, 140, {0, 4.5f, 0.25f}));
  EXPECT_FALSE(discards(g, c, 45, {0.25f, 4.5f, 0}));  // a smooth splat: never clipped
}

TEST(GraphBuildSplatGraph, ConvexBoxEdgeClipsTheOverhang) {
  // Top z = 0 (x > 0, normal +z) and side x = 0 (z < 0, normal -x): a convex edge.
  Cloud c;
  add_grid(c, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  add_grid(c, {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, {-1, 0, 0});
  const SplatGraph g = build(c);
  EXPECT_EQ(g.stats.sharp_edges, 28u);
  EXPECT_EQ(g.surfaces.count(), 2u);
  EXPECT_TRUE(discards(g, c, 40, {-0.25f, 4.5f, 0}));  // top splat beyond the edge
  EXPECT_FALSE(discards(g, c, 40, {0.25f, 4.5f, 0}));
  EXPECT_TRUE(discards(g, c, 140, {0, 4.5f, 0.25f}));  // side splat above the top
  EXPECT_FALSE(discards(g, c, 140, {0, 4.5f, -0.25f}));
}

TEST(GraphBuildSplatGraph, CrossingPlanesAreIntersectionsNotClipped) {
  // Floor z = 0 for x in [-5, 5] and wall x = 0 for z in [-5, 5]: they cross, no boundary.
  Cloud c;
  add_grid(c, {-5, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  add_grid(c, {0, 0, -5}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0});
  const SplatGraph g = build(c);
  EXPECT_EQ(g.stats.sharp_edges, 4 * 28u);
  EXPECT_EQ(g.surfaces.count(), 2u);
  // Away from the grids' own open borders (y = 0.5, 9.5) the crossing splats are surrounded by
  // their surface: intersections, not clipped.
  for (std::size_t i = 0; i < 200; ++i) {
    const Vec3f& p = c.positions[i];
    const bool near_line = (i < 100 ? std::abs(p.x) : std::abs(p.z)) == 0.5f;
    if (!near_line || p.y == 0.5f || p.y == 9.5f) continue;
    EXPECT_EQ(g.classes[i], SplatClass::kIntersection) << i;
    EXPECT_EQ(g.clip.offsets[i + 1], g.clip.offsets[i]) << i;
  }
  EXPECT_EQ(g.stats.intersection_splats, 4 * 8u);
}

TEST(GraphBuildSplatGraph, SecondRowReachingAcrossTheCreaseIsClipped) {
  // Radius 1.6: the floor splat at x = 1.5 reaches x = -0.1, across the crease, and crosses wall
  // splats. Its continuous neighbours surround it (Linsen alone says "intersection"), but all
  // lie on its side of the crease: an edge, clipped.
  const Cloud c = floor_and_wall(1.6f);
  const SplatGraph g = build(c);
  const std::size_t second_row = 41;
  ASSERT_EQ(c.positions[second_row], (Vec3f{1.5f, 4.5f, 0}));
  EXPECT_EQ(g.classes[second_row], SplatClass::kEdge);
  EXPECT_GT(g.clip.offsets[second_row + 1], g.clip.offsets[second_row]);
  EXPECT_TRUE(discards(g, c, second_row, {-0.05f, 4.5f, 0}));
  EXPECT_FALSE(discards(g, c, second_row, {0.25f, 4.5f, 0}));
  // Every splat whose disc crosses the other surface is an edge here. (The third row, x = 2.5,
  // has sharp edges but no crossing: Linsen's "intersection", harmless, nothing to clip.)
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    bool crosses = false;
    for (uint64_t k = g.graph.offsets[i]; k < g.graph.offsets[i + 1]; ++k)
      crosses = crosses || (g.edge_flags[k] & kEdgeCrossing);
    if (crosses) {
      EXPECT_EQ(g.classes[i], SplatClass::kEdge) << i;
    }
  }
  EXPECT_EQ(g.stats.intersection_splats, 16u);
  // Crossing planes with the same radius stay intersections (neighbours on both sides).
  Cloud x;
  x.radius = 1.6f;
  add_grid(x, {-5, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  add_grid(x, {0, 0, -5}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0});
  const SplatGraph gx = build(x);
  EXPECT_EQ(gx.classes[44], SplatClass::kIntersection);  // (-0.5, 4.5, 0)
  EXPECT_EQ(gx.classes[45], SplatClass::kIntersection);  // (0.5, 4.5, 0)
  EXPECT_EQ(gx.clip.offsets[46], gx.clip.offsets[44]);
}

TEST(GraphBuildSplatGraph, SameResultForAnyThreadCount) {
  const Cloud c = floor_and_wall();
  SplatGraph one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = build(c);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = build(c);
  }
  EXPECT_EQ(one.graph.neighbors, two.graph.neighbors);
  EXPECT_EQ(one.edge_flags, two.edge_flags);
  EXPECT_EQ(one.clip.partners, two.clip.partners);
  EXPECT_EQ(one.clip.flags, two.clip.flags);
  EXPECT_EQ(one.surfaces.surface, two.surfaces.surface);
}

TEST(GraphBuildSplatGraph, RejectsBadInputAndOptions) {
  Cloud c = floor_and_wall();
  SplatGraphOptions o;
  o.sharp_threshold = 1.5f;
  EXPECT_THROW(build(c, o), Error);
  o = {};
  o.boundary_gap_degrees = 0;
  EXPECT_THROW(build(c, o), Error);
  c.radii[7] = -1;
  try {
    build(c);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("splat 7"), std::string::npos);
  }
  SplatCloud cloud;
  cloud.positions = c.positions;
  EXPECT_THROW(build_splat_graph(cloud, {}), Error);
}

}  // namespace
}  // namespace splatkit::graph
