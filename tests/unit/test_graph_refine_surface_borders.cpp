// refine_surface_borders: a border that wandered off a crease goes back to it; across a crease
// the side of the noise decides (convex: the surface the splat lies outside of; concave: inside
// of); surfaces that cross keep their splats; fragments are taken splat by splat; a surface no
// primitive explains keeps its border; the same answer for any thread count.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "graph/refine_surface_borders.h"
#include "graph/renumber_surfaces.h"
#include "graph/sphere_overlap_graph.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

struct Scene {
  std::vector<Vec3f> positions, normals;
  std::vector<uint32_t> truth;
  NeighborGraph graph;

  // A grid of size × size splats at spacing 1: origin + (a + 0.5) u + (b - size / 2) v, normal
  // n, moved along n by noise × N(0, 1); true surface `patch`.
  void grid(Vec3f origin, Vec3f u, Vec3f v, Vec3f n, uint32_t patch, int size = 20,
            double noise = 0, uint64_t seed = 1) {
    DeterministicRng rng(seed, patch);
    for (int a = 0; a < size; ++a)
      for (int b = 0; b < size; ++b) {
        const float e = float(noise * rng.normal());
        positions.push_back(origin + u * (a + 0.5f) + v * float(b - size / 2) + n * e);
        normals.push_back(n);
        truth.push_back(patch);
      }
  }
  void connect() {
    graph = sphere_overlap_graph(positions, std::vector<float>(positions.size(), 0.75f));
  }
  Segmentation labels(std::vector<uint32_t> l) const {
    uint32_t count = 0;
    for (uint32_t s : l) count = std::max(count, s + 1);
    return renumber_surfaces(l, count);
  }
  Segmentation refine(const Segmentation& seg, RefineBordersOptions o = {},
                      RefineBordersInfo* info = nullptr) const {
    return refine_surface_borders(graph, positions, normals, seg, o, info);
  }
};

constexpr Vec3f kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

// The edge of a box (solid at x > 0, z < 0): top z = 0 (normal +z, patch 0) and side x = 0
// (normal -x, patch 1), a convex 90° crease along y.
Scene box_edge(double noise = 0, int size = 20) {
  Scene s;
  s.grid({0, 0, 0}, kX, kY, kZ, 0, size, noise);
  s.grid({0, 0, 0}, kZ * -1, kY, kX * -1, 1, size, noise);
  s.connect();
  return s;
}

// A floor z = 0 (normal +z, patch 0) meeting a wall x = 0 (normal +x, patch 1): concave.
Scene floor_and_wall(double noise = 0) {
  Scene s;
  s.grid({0, 0, 0}, kX, kY, kZ, 0, 20, noise);
  s.grid({0, 0, 0}, kZ, kY, kX, 1, 20, noise);
  s.connect();
  return s;
}

TEST(GraphRefineSurfaceBorders, WanderedBorderGoesBackToTheCrease) {
  const Scene s = box_edge(0, 40);
  // The first three columns of the top (x = 0.5, 1.5, 2.5) went to the side (7 % of its splats:
  // the side's plane still explains it).
  std::vector<uint32_t> wrong = s.truth;
  for (std::size_t i = 0; i < 120; ++i) wrong[i] = 1;
  RefineBordersInfo info;
  const Segmentation seg = s.refine(s.labels(wrong), {}, &info);
  EXPECT_EQ(seg.surface, s.truth);
  EXPECT_EQ(seg.sizes, (std::vector<uint32_t>{1600, 1600}));
  EXPECT_EQ(info.planes, 2u);
  EXPECT_EQ(info.moved, 120u);
  EXPECT_EQ(info.rounds, 4u);  // a column per round, then a round that changes nothing
}

TEST(GraphRefineSurfaceBorders, ConvexCreaseTheSurfaceTheSplatLiesOutsideOf) {
  Scene s = box_edge(0.2);
  // A top splat next to the crease, (0.5, 0, 0), pushed 0.55 up by its noise: 0.55 from the
  // top's plane but 0.5 from the side's. At a convex crease every top splat lies beneath the
  // side's extension (x > 0), so it belongs to the top.
  const std::size_t k = 10;
  ASSERT_EQ(s.positions[k].x, 0.5f);
  s.positions[k] = {0.5f, 0, 0.55f};
  std::vector<uint32_t> l = s.truth;
  l[k] = 1;
  EXPECT_EQ(s.refine(s.labels(l)).surface[k], 0u);
  RefineBordersOptions nearest;
  nearest.crease_sine = 2;  // no crease is ever clear: the nearest surface wins
  EXPECT_EQ(s.refine(s.labels(l), nearest).surface[k], 1u);
}

TEST(GraphRefineSurfaceBorders, ConcaveCreaseTheSurfaceTheSplatLiesInsideOf) {
  Scene s = floor_and_wall(0.2);
  // A floor splat pushed 0.55 below the floor: 0.5 from the wall's plane, but a floor splat is
  // never behind the wall (x < 0) and a wall splat never below the floor.
  const std::size_t k = 10;
  s.positions[k] = {0.5f, 0, -0.55f};
  std::vector<uint32_t> l = s.truth;
  l[k] = 1;
  EXPECT_EQ(s.refine(s.labels(l)).surface[k], 0u);
  RefineBordersOptions nearest;
  nearest.crease_sine = 2;
  EXPECT_EQ(s.refine(s.labels(l), nearest).surface[k], 1u);
}

TEST(GraphRefineSurfaceBorders, CrossingSurfacesKeepTheirSplats) {
  // Planes z = 0 and x = 0 crossing along y, each on both sides of the other.
  Scene s;
  s.grid({-10, 0, 0}, kX, kY, kZ, 0);
  s.grid({0, 0, -10}, kZ, kY, kX, 1);
  s.connect();
  RefineBordersInfo info;
  EXPECT_EQ(s.refine(s.labels(s.truth), {}, &info).surface, s.truth);
  EXPECT_EQ(info.moved, 0u);
}

TEST(GraphRefineSurfaceBorders, FragmentsAreTakenSplatBySplat) {
  Scene s = box_edge(0.05);
  std::vector<uint32_t> l = s.truth;
  // A 3 × 3 fragment (under min_surface_size) and an 8 × 8 island that the top's plane
  // explains, both on the top; and a 4 × 4 fragment on the side.
  for (int a = 5; a < 8; ++a)
    for (int b = 2; b < 5; ++b) l[a * 20 + b] = 2;
  for (int a = 10; a < 18; ++a)
    for (int b = 8; b < 16; ++b) l[a * 20 + b] = 3;
  for (int a = 6; a < 10; ++a)
    for (int b = 6; b < 10; ++b) l[400 + a * 20 + b] = 4;
  RefineBordersInfo info;
  const Segmentation seg = s.refine(s.labels(l), {}, &info);
  EXPECT_EQ(seg.surface, s.truth);
  EXPECT_EQ(info.joined, 1u);  // the island; the two small ones have no model of their own
  EXPECT_EQ(info.planes, 2u);
}

TEST(GraphRefineSurfaceBorders, LeakedSurfaceIsSplitIntoItsFaces) {
  // The top (20 × 20) and a smaller side (14 × 14) in one surface, as a segmentation that
  // leaked across the crease gives them: split into two planes, then the border settles.
  Scene s;
  s.grid({0, 0, 0}, kX, kY, kZ, 0, 20, 0.05);
  s.grid({0, 0, 0}, kZ * -1, kY, kX * -1, 1, 14, 0.05);
  s.connect();
  RefineBordersInfo info;
  const Segmentation seg = s.refine(s.labels(std::vector<uint32_t>(s.truth.size(), 0)), {}, &info);
  EXPECT_EQ(seg.surface, s.truth);
  EXPECT_EQ(info.split, 1u);
  EXPECT_EQ(info.planes, 2u);
}

TEST(GraphRefineSurfaceBorders, UnexplainedSurfaceKeepsItsBorder) {
  // The side is a free-form surface (x = 0.6 sin(z) sin(y / 2), normals its gradient's): no
  // plane, sphere or cylinder explains it, so the wrong columns stay.
  Scene s = box_edge();
  for (std::size_t i = 400; i < 800; ++i) {
    Vec3f& p = s.positions[i];
    p.x = 0.6f * std::sin(p.z) * std::sin(p.y / 2);
    const Vec3f g{-1, 0.3f * std::sin(p.z) * std::cos(p.y / 2),
                  0.6f * std::cos(p.z) * std::sin(p.y / 2)};
    s.normals[i] = normalized(g);
  }
  s.connect();
  std::vector<uint32_t> l = s.truth;
  for (std::size_t i = 0; i < 20; ++i) l[i] = 1;
  RefineBordersInfo info;
  EXPECT_EQ(s.refine(s.labels(l), {}, &info).surface, s.labels(l).surface);
  EXPECT_EQ(info.unexplained, 1u);
  EXPECT_EQ(info.planes, 1u);
}

TEST(GraphRefineSurfaceBorders, SameAnswerForAnyThreadCountAndRoundsZeroIsTheInput) {
  const Scene s = box_edge(0.3);
  std::vector<uint32_t> l = s.truth;
  for (std::size_t i = 0; i < 40; ++i) l[i] = 1;
  Segmentation one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = s.refine(s.labels(l));
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = s.refine(s.labels(l));
  }
  EXPECT_EQ(one.surface, two.surface);
  EXPECT_EQ(one.sizes, two.sizes);
  RefineBordersOptions none;
  none.rounds = 0;
  EXPECT_EQ(s.refine(s.labels(l), none).surface, s.labels(l).surface);
}

TEST(GraphRefineSurfaceBorders, RejectsMismatchedInput) {
  const Scene s = box_edge();
  Segmentation seg = s.labels(s.truth);
  seg.surface.pop_back();
  EXPECT_THROW(s.refine(seg), std::invalid_argument);
  seg = s.labels(s.truth);
  seg.surface[3] = 7;  // >= count()
  EXPECT_THROW(s.refine(seg), std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
