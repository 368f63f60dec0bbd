// split_small_faces: a ledge of 36 splats standing out of a wall, joined to it, comes off as a
// face of its own; a single row of splats off the wall with turned normals (too narrow to be a
// face) and a ledge under min_size stay; offset_scales 0 changes nothing.
#include <gtest/gtest.h>

#include <vector>

#include "graph/sphere_overlap_graph.h"
#include "graph/split_small_faces.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::graph {
namespace {

constexpr float kSpacing = 0.05f, kRadius = 0.04f;

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<float> radii;
  std::vector<uint32_t> truth;
  DeterministicRng rng{7};
  void add(Vec3f p, Vec3f n, uint32_t patch) {
    positions.push_back(p);
    normals.push_back(n);
    radii.push_back(kRadius);
    truth.push_back(patch);
  }
  // The wall y = 0, x in [0, 1.95], z in [0, 1.45], noise 0.002 along y.
  void wall() {
    for (int a = 0; a < 40; ++a)
      for (int b = 0; b < 30; ++b)
        add({kSpacing * float(a), float(0.002 * rng.normal()), kSpacing * float(b)}, {0, 1, 0}, 0);
  }
  // A horizontal ledge at z = 0.75 standing out of the wall: `rows` rows from y = 0.05, x in
  // [0.5, 0.5 + 0.05 (cols - 1)], noise 0.002 along z.
  void ledge(int rows, int cols) {
    for (int r = 1; r <= rows; ++r)
      for (int k = 0; k < cols; ++k)
        add({0.5f + kSpacing * float(k), kSpacing * float(r), float(0.75 + 0.002 * rng.normal())},
            {0, 0, 1}, 1);
  }
  Segmentation one_surface() const {
    return {std::vector<uint32_t>(positions.size(), 0), {uint32_t(positions.size())}};
  }
};

TEST(GraphSplitSmallFaces, ALedgeComesOff) {
  Cloud c;
  c.wall();
  c.ledge(6, 6);
  const NeighborGraph g = sphere_overlap_graph(c.positions, c.radii);
  uint32_t split = 0;
  const Segmentation out =
      split_small_faces(g, c.positions, c.normals, c.radii, c.one_surface(), {}, &split);
  EXPECT_EQ(split, 1u);
  ASSERT_EQ(out.count(), 2u);
  for (std::size_t i = 0; i < c.truth.size(); ++i) EXPECT_EQ(out.surface[i], c.truth[i]) << i;

  SplitSmallFacesOptions larger;
  larger.min_size = 37;
  EXPECT_EQ(split_small_faces(g, c.positions, c.normals, c.radii, c.one_surface(), larger).count(),
            1u);
  SplitSmallFacesOptions none;
  none.offset_scales = 0;
  EXPECT_EQ(split_small_faces(g, c.positions, c.normals, c.radii, c.one_surface(), none).count(),
            1u);
}

TEST(GraphSplitSmallFaces, ARowOfSplatsIsNotAFace) {
  Cloud c;
  c.wall();
  c.ledge(1, 30);  // 30 splats in one row: off the wall, normals turned, one splat wide
  const NeighborGraph g = sphere_overlap_graph(c.positions, c.radii);
  uint32_t split = 1;
  const Segmentation out =
      split_small_faces(g, c.positions, c.normals, c.radii, c.one_surface(), {}, &split);
  EXPECT_EQ(split, 0u);
  EXPECT_EQ(out.count(), 1u);
}

}  // namespace
}  // namespace splatkit::graph
