// sphere_overlap_graph: the grid gives exactly SpatialIndex::sphere_overlaps' graph (and brute
// force's), with big splats, zero radii, duplicates and far-apart clusters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "graph/overlap_grid.h"
#include "graph/sphere_overlap_graph.h"
#include "simd_level_test.h"
#include "splatkit/error.h"
#include "splatkit/spatial_index.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::graph {
namespace {

NeighborGraph brute_force(const std::vector<Vec3f>& c, const std::vector<float>& r) {
  NeighborGraph g;
  g.offsets.push_back(0);
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (std::size_t j = 0; j < c.size(); ++j) {
      const float sum = r[i] + r[j];
      if (j != i && squared_distance(c[i], c[j]) < sum * sum) g.neighbors.push_back(uint32_t(j));
    }
    g.offsets.push_back(g.neighbors.size());
  }
  return g;
}

// The tests that compare the vector paths run at every SIMD level the CPU has (simd_level() is
// capped at the level, and the same level is passed as the limit).
using GraphSphereOverlapGraphAt = SimdLevelTest;
INSTANTIATE_TEST_SUITE_P(Simd, GraphSphereOverlapGraphAt, kEverySimdLevel, simd_level_param_name);

void expect_same(const NeighborGraph& a, const NeighborGraph& b, const char* what) {
  EXPECT_EQ(a.offsets, b.offsets) << what;
  EXPECT_EQ(a.neighbors, b.neighbors) << what;
}

TEST(GraphSphereOverlapGraph, TwoSplatsTouchingIsNoEdgeOverlappingIs) {
  const std::vector<Vec3f> c{{0, 0, 0}, {2, 0, 0}, {0, 2.5f, 0}};
  // 0 and 1: |C| = 2 = 1 + 1, touching, not overlapping; 0 and 2: 2.5 < 1 + 2.5; 1 and 2:
  // sqrt(10.25) < 3.5.
  const NeighborGraph g = sphere_overlap_graph(c, std::vector<float>{1, 1, 2.5f});
  EXPECT_EQ(g.offsets, (std::vector<uint64_t>{0, 1, 2, 4}));
  EXPECT_EQ(g.neighbors, (std::vector<uint32_t>{2, 2, 0, 1}));
}

TEST_P(GraphSphereOverlapGraphAt, RandomCloudsWithBigSplatsMatchBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int round = 0; round < 12; ++round) {
    const std::size_t n = round == 7 ? 1500 : 1 + rng() % 1500;
    std::vector<Vec3f> c(n);
    std::vector<float> r(n);
    for (std::size_t i = 0; i < n; ++i) {
      c[i] = {u(rng), u(rng), round % 3 == 0 ? 0.0f : u(rng) * 0.2f};  // planes and slabs
      r[i] = 0.05f * (1 + 0.2f * u(rng));
      if (rng() % 200 == 0) r[i] *= 1 + float(rng() % 30);  // big splats, some huge
      if (rng() % 300 == 0) r[i] = 0;
      if (i > 0 && rng() % 100 == 0) c[i] = c[i - 1];  // duplicates
    }
    if (round == 5) c[0] = {1000, -1000, 3};  // a far-away splat: a long, empty grid
    if (round == 7) r[n / 2] = 1000;          // its cell scan is over budget: the kd-tree answers
    expect_same(sphere_overlap_graph(c, r, level()), brute_force(c, r), "brute force");
  }
}

TEST_P(GraphSphereOverlapGraphAt, LongRowsMatchBruteForce) {
  // Radii of several times the spacing: rows of up to about 200 neighbours (the ranking sort
  // takes rows up to 64, std::sort the longer ones; the other tests have short rows).
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec3f> c;
  std::vector<float> r;
  for (int i = 0; i < 2000; ++i) {
    c.push_back({u(rng), u(rng), 0.05f * u(rng)});
    r.push_back(0.06f + 0.04f * u(rng));
  }
  const NeighborGraph expected = brute_force(c, r);
  std::size_t longest = 0;
  for (std::size_t i = 0; i < c.size(); ++i) longest = std::max(longest, expected.row(i).size());
  EXPECT_GT(longest, 64u);
  expect_same(sphere_overlap_graph(c, r, level()), expected, "brute force");
}

TEST_P(GraphSphereOverlapGraphAt, ShapesMatchTheKdTree) {
  for (ShapeKind kind : {ShapeKind::kCadPart, ShapeKind::kTwoSpheres, ShapeKind::kTorus}) {
    ShapeOptions so;
    so.kind = kind;
    so.points = 20000;
    so.random = kind == ShapeKind::kTorus;
    const SplatCloud cloud = make_shape(so);
    const NeighborGraph expected = SpatialIndex(cloud.positions).sphere_overlaps(cloud.radii);
    expect_same(sphere_overlap_graph(cloud.positions, cloud.radii), expected, "kd-tree");
  }
}

// Cells that hold few splats grow (with AVX-512, up to twice 2 R) and the graph stays exact: a
// jittered grid on a plane and in a thin slab, radii alike, about 2 splats per cell of 2 R.
TEST_P(GraphSphereOverlapGraphAt, SparseCellsGrowAndKeepTheGraph) {
  std::mt19937 rng(47);
  std::uniform_real_distribution<float> u(-0.3f, 0.3f);
  for (int slab = 0; slab < 2; ++slab) {
    std::vector<Vec3f> c;
    std::vector<float> r;
    for (int i = 0; i < 70; ++i)
      for (int j = 0; j < 70; ++j) {
        c.push_back({float(i) + u(rng), float(j) + u(rng), slab ? 2 * u(rng) : 0.0f});
        r.push_back(0.75f + 0.05f * u(rng));
      }
    const float R = overlap::small_radius(r);
    const overlap::Grid fixed = overlap::make_grid(c, R, false), grown = overlap::make_grid(c, R, true);
    EXPECT_GE(1 / fixed.inv_cell, 2.0 * R);
    EXPECT_GT(1 / grown.inv_cell, 1.2 / fixed.inv_cell);  // grows on the plane and in the slab
    EXPECT_LE(1 / grown.inv_cell, 2.0 / fixed.inv_cell * (1 + 1e-12));
    expect_same(sphere_overlap_graph(c, r, level()), brute_force(c, r), "brute force");
  }
}

// A few splats very far from the rest (one at 1e20, one at -1e30, two copies at 3e25) must not
// set the grid's cell size: the graph stays exact (the copies overlap each other), with small
// and with huge radii on the far splats.
TEST_P(GraphSphereOverlapGraphAt, FarOutliersKeepTheGraphExact) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0, 1);
  for (int round = 0; round < 3; ++round) {
    std::vector<Vec3f> c;
    std::vector<float> r;
    for (int i = 0; i < 6000; ++i) {
      c.push_back({u(rng), u(rng), 0.01f * u(rng)});
      r.push_back(0.012f * (1 + 0.3f * u(rng)));
    }
    const float far_r = round == 1 ? 1e20f : 0.012f;  // round 1: radii as large as the distance
    const std::size_t at[] = {0, 2999, 3000, 5999};
    c[at[0]] = {1e20f, 0, 0};
    c[at[1]] = {-1e30f, 0.5f, 0.5f};
    c[at[2]] = c[at[3]] = {3e25f, -3e25f, 1};
    for (std::size_t i : at) r[i] = far_r;
    if (round == 2) {  // a far cluster big enough to pass the grid's sampled quantiles
      for (int i = 0; i < 100; ++i) {
        c[100 + i] = {5e6f + u(rng), 0, 0};
        r[100 + i] = 0.012f;
      }
    }
    const NeighborGraph expected = brute_force(c, r);
    EXPECT_EQ(expected.row(at[2]).size(), 1u);  // the far copies overlap each other only
    expect_same(sphere_overlap_graph(c, r, level()), expected, "brute force");
  }
}

// The marks of sphere_overlap_graph(..., sharp, marks) against a direct test of every entry.
void expect_marks(const std::vector<Vec3f>& c, const std::vector<float>& r,
                  const std::vector<Vec3f>& n, float threshold, const NeighborGraph& expected) {
  {
    SharpEdgeMarks marks;
    const NeighborGraph g = sphere_overlap_graph(c, r, SharpEdges{n, threshold, 4}, marks);
    expect_same(g, expected, "brute force, with marks");
    std::vector<uint8_t> flags;
    std::vector<uint32_t> rows;
    for (std::size_t i = 0; i < c.size(); ++i) {
      bool any = false;
      for (uint32_t j : expected.row(i)) {
        const bool sharp = !(dot(n[i], n[j]) >= threshold);
        flags.push_back(sharp ? 4 : 0);
        any = any || sharp;
      }
      if (any) rows.push_back(uint32_t(i));
    }
    EXPECT_EQ(marks.flags, flags);
    EXPECT_EQ(marks.rows, rows);
    // Lent arrays: the same graph and marks, and the arrays given back bit for bit (NaN normals
    // included), in new buffers when the grid borrowed them.
    std::vector<Vec3f> lc = c, ln = n;
    std::vector<float> lr = r;
    SharpEdgeMarks lent_marks;
    const NeighborGraph lg = sphere_overlap_graph(LentSplats{lc, lr, ln}, threshold, 4, lent_marks);
    expect_same(lg, expected, "brute force, lent arrays");
    EXPECT_EQ(lent_marks.flags, flags);
    EXPECT_EQ(lent_marks.rows, rows);
    auto same_bytes = [](const auto& a, const auto& b) {
      return a.size() == b.size() &&
             (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
    };
    EXPECT_TRUE(same_bytes(lc, c));
    EXPECT_TRUE(same_bytes(lr, r));
    EXPECT_TRUE(same_bytes(ln, n));
  }
}

TEST_P(GraphSphereOverlapGraphAt, SharpMarksMatchADirectTest) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int round = 0; round < 9; ++round) {
    // Round 4: rows of about 50 (past the 16 one AVX-512 register holds); round 7: one radius
    // of 1000, whose cell scan is over budget (the kd-tree answers, marked afterwards); the
    // others: rows of 1-10, with big splats merged into them.
    const std::size_t count = round == 4 || round == 7 ? 1500 : 1 + rng() % 1500;
    std::vector<Vec3f> c(count), n(count);
    std::vector<float> r(count);
    for (std::size_t i = 0; i < count; ++i) {
      c[i] = {u(rng), u(rng), u(rng) * 0.2f};
      r[i] = (round == 4 ? 0.12f : 0.05f) * (1 + 0.2f * u(rng));
      if (rng() % 200 == 0) r[i] *= 1 + float(rng() % 30);  // big splats: rows merged with pairs
      // Normals near +z, some tipped past the threshold, a few not numbers.
      n[i] = normalized(Vec3f{0.6f * u(rng), 0.6f * u(rng), 1});
      if (rng() % 400 == 0) n[i].x = std::numeric_limits<float>::quiet_NaN();
    }
    if (round == 7) r[count / 2] = 1000;
    const NeighborGraph expected = brute_force(c, r);
    if (round == 4) {
      std::size_t longest = 0;
      for (std::size_t i = 0; i < count; ++i) longest = std::max(longest, expected.row(i).size());
      EXPECT_GT(longest, 32u);
    }
    expect_marks(c, r, n, 0.9f, expected);
  }
  // A shape with true normals: its creases are the sharp edges.
  ShapeOptions so;
  so.kind = ShapeKind::kCadPart;
  so.points = 20000;
  const SplatCloud cad = make_shape(so);
  expect_marks(cad.positions, cad.radii, cad.normals, 0.9f,
               SpatialIndex(cad.positions).sphere_overlaps(cad.radii));
  // The early answers: nothing, all radii zero, almost all zero (the kd-tree's answer).
  const std::vector<Vec3f> same(5, Vec3f{1, 2, 3});
  std::vector<Vec3f> tipped(5, Vec3f{0, 0, 1});
  tipped[3] = {1, 0, 0};
  expect_marks({}, {}, {}, 0.9f, brute_force({}, {}));
  expect_marks(same, std::vector<float>(5, 0), tipped, 0.9f,
               brute_force(same, std::vector<float>(5, 0)));
  std::vector<float> mostly_zero(5, 0);
  mostly_zero[2] = 1;
  expect_marks(same, mostly_zero, tipped, 0.9f, brute_force(same, mostly_zero));
  std::vector<Vec3f> three(3, Vec3f{0, 0, 1});
  EXPECT_THROW(
      {
        SharpEdgeMarks marks;
        sphere_overlap_graph(cad.positions, cad.radii, SharpEdges{three, 0.9f, 1}, marks);
      },
      std::invalid_argument);
}

TEST(GraphSphereOverlapGraph, DegenerateInputs) {
  EXPECT_EQ(sphere_overlap_graph({}, {}).offsets, (std::vector<uint64_t>{0}));
  const std::vector<Vec3f> same(5, Vec3f{1, 2, 3});
  // All radii zero: nothing overlaps, even at the same point.
  EXPECT_TRUE(sphere_overlap_graph(same, std::vector<float>(5, 0)).neighbors.empty());
  const NeighborGraph all = sphere_overlap_graph(same, std::vector<float>(5, 0.1f));
  EXPECT_EQ(all.neighbors.size(), 20u);
  // Almost all radii zero (the 99.9th percentile is 0): the kd-tree's answer.
  std::vector<float> r(5, 0);
  r[2] = 1;
  EXPECT_EQ(sphere_overlap_graph(same, r).neighbors,
            (std::vector<uint32_t>{2, 2, 0, 1, 3, 4, 2, 2}));
  EXPECT_THROW(sphere_overlap_graph(same, std::vector<float>(4, 1)), std::invalid_argument);
  EXPECT_THROW(sphere_overlap_graph(same, std::vector<float>{1, 1, -1, 1, 1}),
               std::invalid_argument);
  std::vector<Vec3f> bad = same;
  bad[1].y = std::numeric_limits<float>::infinity();
  EXPECT_THROW(sphere_overlap_graph(bad, std::vector<float>(5, 1)), Error);
}

}  // namespace
}  // namespace splatkit::graph
