// merge_coplanar_surfaces: pieces of one noisy plane join, across an edge and across a gap; the
// treads of a step (parallel, half a metre apart) and the riser between them stay apart; a
// fillet rising from a plane stays apart; scales 0 changes nothing; a bay standing out of a wall
// with relief joins it within the biweight's support, a wall as large at that offset does not.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/merge_coplanar_surfaces.h"
#include "graph/sphere_overlap_graph.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

constexpr float kSpacing = 0.05f, kRadius = 0.04f;

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<float> radii;
  std::vector<uint32_t> label;
  DeterministicRng rng{11};
  // A grid on a plane: origin + a·u + b·v for a < na, b < nb steps of kSpacing, noise 0.003
  // along the normal u × v, normals tilted by noise of about 3 degrees.
  void grid(Vec3f origin, Vec3f u, Vec3f v, int na, int nb, uint32_t id, double noise = 0.003,
            float radius = kRadius) {
    const Vec3f n = cross(u, v);
    for (int a = 0; a < na; ++a)
      for (int b = 0; b < nb; ++b) {
        const float e = float(noise * rng.normal());
        positions.push_back(origin + u * (kSpacing * float(a)) + v * (kSpacing * float(b)) + n * e);
        const Vec3f t{float(0.05 * rng.normal()), float(0.05 * rng.normal()),
                      float(0.05 * rng.normal())};
        const Vec3f m = n + t - n * dot(n, t);
        normals.push_back(m / std::sqrt(dot(m, m)));
        radii.push_back(radius);
        label.push_back(id);
      }
  }
  Segmentation segmentation(uint32_t count) const {
    Segmentation s;
    s.surface = label;
    s.sizes.assign(count, 0);
    for (uint32_t l : label) ++s.sizes[l];
    return s;
  }
  NeighborGraph graph() const { return sphere_overlap_graph(positions, radii); }
};

const Vec3f kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

TEST(GraphMergeCoplanarSurfaces, PiecesOfOnePlaneJoinAcrossAnEdgeAndAGap) {
  Cloud c;
  c.grid({0, 0, 0}, kX, kY, 40, 30, 0);     // x in [0, 1.95]
  c.grid({2.0f, 0, 0}, kX, kY, 20, 30, 1);  // adjacent: x in [2, 2.95]
  c.grid({4.0f, 0, 0}, kX, kY, 20, 30, 2);  // 1 m of gap: x in [4, 4.95]
  const NeighborGraph g = c.graph();
  CoplanarMergeInfo info;
  const Segmentation out =
      merge_coplanar_surfaces(g, c.positions, c.normals, c.radii, c.segmentation(3), {}, &info);
  EXPECT_EQ(out.count(), 1u);
  EXPECT_EQ(info.planar, 3u);
  EXPECT_EQ(info.joined, 2u);
  EXPECT_EQ(info.disjoint, 1u);

  CoplanarMergeOptions adjacent_only;
  adjacent_only.join_disjoint = false;
  const Segmentation two =
      merge_coplanar_surfaces(g, c.positions, c.normals, c.radii, c.segmentation(3), adjacent_only);
  ASSERT_EQ(two.count(), 2u);
  EXPECT_EQ(two.sizes[0], 60u * 30u);
  EXPECT_EQ(two.sizes[1], 20u * 30u);

  CoplanarMergeOptions none;
  none.offset_scales = 0;
  const Segmentation same =
      merge_coplanar_surfaces(g, c.positions, c.normals, c.radii, c.segmentation(3), none);
  EXPECT_EQ(same.surface, c.label);
}

TEST(GraphMergeCoplanarSurfaces, TheTreadsAndTheRiserOfAStepStayApart) {
  Cloud c;
  c.grid({0, 0, 0}, kX, kY, 40, 30, 0);         // lower tread, z = 0, x < 2
  c.grid({2.0f, 0, 0.05f}, kZ, kY, 10, 30, 1);  // riser x = 2, z in [0.05, 0.5]
  c.grid({2.05f, 0, 0.5f}, kX, kY, 40, 30, 2);  // upper tread z = 0.5
  const NeighborGraph g = c.graph();
  CoplanarMergeInfo info;
  const Segmentation out =
      merge_coplanar_surfaces(g, c.positions, c.normals, c.radii, c.segmentation(3), {}, &info);
  EXPECT_EQ(out.surface, c.label);
  EXPECT_EQ(info.joined, 0u);
}

TEST(GraphMergeCoplanarSurfaces, AFilletStaysApart) {
  // A quarter cylinder of radius 1 (axis along y through x = 1, z = 1) rising tangentially from
  // the plane z = 0 at x = 1 to vertical at x = 2: its foot lies on the plane, its normals turn
  // through 90 degrees: its robust plane is the tangent plane half way up, 45 degrees from the
  // plane's (it counts as planar: half its normals lie within 22.5 degrees of that plane).
  Cloud c;
  c.grid({-1.0f, 0, 0}, kX, kY, 40, 30, 0);  // x in [-1, 0.95]
  for (int k = 0; k < 32; ++k)
    for (int b = 0; b < 30; ++b) {
      const double t = kSpacing * k;
      c.positions.push_back({float(1 + std::sin(t)), kSpacing * float(b), float(1 - std::cos(t))});
      c.normals.push_back({float(-std::sin(t)), 0, float(std::cos(t))});
      c.radii.push_back(kRadius);
      c.label.push_back(1);
    }
  const NeighborGraph g = c.graph();
  CoplanarMergeInfo info;
  const Segmentation out =
      merge_coplanar_surfaces(g, c.positions, c.normals, c.radii, c.segmentation(2), {}, &info);
  EXPECT_EQ(info.joined, 0u);
  EXPECT_EQ(out.surface, c.label);
}

// A wall z = 0 with relief (noise 0.1: robust scale about 0.1) and, beside it, a piece 0.4 m in
// front of it (4 of the wall's scales: beyond 3, within the biweight's 4.685), flat within
// 0.003; splats of radius 0.15 (a diameter under the step), which share edges across it.
Cloud wall_and_piece(int piece_rows) {
  Cloud c;
  c.grid({0, 0, 0}, kX, kY, 40, 30, 0, 0.1, 0.15f);
  c.grid({2.0f, 0, 0.4f}, kX, kY, piece_rows, 30, 1, 0.003, 0.15f);
  return c;
}

TEST(GraphMergeCoplanarSurfaces, ABayJoinsAWallWithReliefAWallAsLargeDoesNot) {
  const Cloud bay = wall_and_piece(10);  // a quarter of the wall's size
  const NeighborGraph g = bay.graph();
  CoplanarMergeInfo info;
  EXPECT_EQ(merge_coplanar_surfaces(g, bay.positions, bay.normals, bay.radii, bay.segmentation(2),
                                    {}, &info)
                .count(),
            1u);
  EXPECT_EQ(info.joined, 1u);
  CoplanarMergeOptions no_relief;
  no_relief.relief_scales = 0;
  EXPECT_EQ(merge_coplanar_surfaces(g, bay.positions, bay.normals, bay.radii, bay.segmentation(2),
                                    no_relief)
                .surface,
            bay.label);

  // As large as the wall: two planes, since the wall is not within the piece's own support.
  const Cloud two = wall_and_piece(40);
  const NeighborGraph g2 = two.graph();
  EXPECT_EQ(
      merge_coplanar_surfaces(g2, two.positions, two.normals, two.radii, two.segmentation(2), {})
          .surface,
      two.label);
}

}  // namespace
}  // namespace splatkit::graph
