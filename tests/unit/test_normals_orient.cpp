// orient_normals_mst and orient_normals_viewpoint: closed shapes end up 100 % outward from random
// signs (sphere, torus, the CAD part with PCA and with crease-sharp robust normals), separate
// components each oriented, tiny clouds, byte-identical results for 1 and 2 threads, a noise
// tail off a plane taking the plane's sign, points where faces meet taking their neighbours'
// mean.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "normals/neighborhood_pca.h"
#include "normals/orient_normals_mst.h"
#include "normals/orient_normals_viewpoint.h"
#include "normals/robust_normals.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit {
namespace {

SplatCloud shape(ShapeKind kind, std::size_t points) {
  ShapeOptions o;
  o.kind = kind;
  o.points = points;
  return make_shape(o);
}

// PCA normals over 16-rows (canonical sign, so about half point inward), and their variations.
std::vector<Vec3f> pca_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::vector<float>* variation = nullptr) {
  const std::size_t n = positions.size(), k = 16;
  std::vector<uint32_t> rows(n * k);
  index.knn_all(k, rows);
  std::vector<Vec3f> normals(n);
  if (variation) variation->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const PcaNormal pca = neighborhood_pca(positions, std::span(rows).subspan(i * k, k));
    normals[i] = pca.normal;
    if (variation) (*variation)[i] = static_cast<float>(surface_variation(pca));
  }
  return normals;
}

void flip_randomly(std::vector<Vec3f>& normals, uint64_t seed) {
  DeterministicRng rng(seed);
  for (Vec3f& n : normals)
    if (rng.next() & 1) n = -n;
}

// Points whose normal points inward (dot with the true outward normal <= 0), among those whose
// unoriented normal is within 60° of the truth: a normal that is wrong by more (PCA at the tip of
// the 60° wedge, where it belongs to neither face) has no meaningful outward side.
std::size_t count_inward(const std::vector<Vec3f>& normals, const std::vector<Vec3f>& truth,
                         std::size_t* meaningless = nullptr) {
  std::size_t inward = 0, skipped = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const float d = dot(normals[i], truth[i]);
    if (std::fabs(d) < 0.5f) {
      ++skipped;
      continue;
    }
    inward += d < 0;
  }
  if (meaningless) *meaningless = skipped;
  return inward;
}

TEST(NormalsOrient, ClosedShapesPointOutward) {
  for (ShapeKind kind : {ShapeKind::kSphere, ShapeKind::kTorus, ShapeKind::kCadPart}) {
    const SplatCloud c = shape(kind, 20000);
    const SpatialIndex index(c.positions);
    std::vector<Vec3f> normals = c.normals;  // exact normals, random signs
    flip_randomly(normals, 1);
    OrientStats stats = orient_normals_mst(index, c.positions, normals);
    std::size_t meaningless = 0;
    EXPECT_EQ(count_inward(normals, c.normals, &meaningless), 0u)
        << shape_kind_name(kind) << " exact";
    EXPECT_EQ(meaningless, 0u);
    EXPECT_EQ(stats.components, 1u);
    EXPECT_GT(stats.flipped, 5000u);

    normals = pca_normals(index, c.positions);
    flip_randomly(normals, 2);
    orient_normals_mst(index, c.positions, normals);
    // PCA at the tip of the 60° wedge gives a normal ~30° off one face and ~150° off the other,
    // flipping sign between neighbours: one such point may end up on the wrong side.
    const bool cad = kind == ShapeKind::kCadPart;
    EXPECT_LE(count_inward(normals, c.normals, &meaningless), cad ? 1u : 0u)
        << shape_kind_name(kind) << " pca";
    EXPECT_LE(meaningless, cad ? 20u : 0u);
  }
}

TEST(NormalsOrient, SharpCreasesAndTheThinWedge) {
  // Robust normals jump by 90° and 120° at the CAD part's creases (the bevel's 60° wedge): n_i·n_j
  // is ~0 or negative across them for a consistent pair, and across the wedge's tip the kNN graph
  // joins the two faces. The mirrored agreement still reads every such pair right.
  const SplatCloud c = shape(ShapeKind::kCadPart, 20000);
  const SpatialIndex index(c.positions);
  std::vector<float> variation;
  std::vector<Vec3f> robust = pca_normals(index, c.positions, &variation);
  robust_normals(index, c.positions, variation, robust);
  flip_randomly(robust, 3);
  const OrientStats stats = orient_normals_mst(index, c.positions, robust);
  std::size_t meaningless = 0;
  EXPECT_EQ(count_inward(robust, c.normals, &meaningless), 0u);
  // Points within half a spacing of the rims of the hole and the boss, which this coarse sample
  // resolves poorly, may take the flat face's normal (67 of 20000 here; 8 of 200000 at 200k).
  EXPECT_LE(meaningless, 100u);
  EXPECT_EQ(stats.components, 1u);
}

TEST(NormalsOrient, NoisyCadPart) {
  // Noise of 0.125 % of the diagonal (half a spacing here) tilts short edges far out of the
  // tangent plane; the mirrored agreement applied everywhere turned about half of the part
  // inward. Near-parallel pairs use plain n_i·n_j, so only a few points at the creases, whose
  // noisy normals are ambiguous, may end up inward.
  ShapeOptions o;
  o.kind = ShapeKind::kCadPart;
  o.points = 20000;
  o.noise = 0.00125;
  const SplatCloud c = make_shape(o);
  const SpatialIndex index(c.positions);
  std::vector<float> variation;
  std::vector<Vec3f> normals = pca_normals(index, c.positions, &variation);
  for (int method = 0; method < 2; ++method) {
    std::vector<Vec3f> n = normals;
    if (method == 1) robust_normals(index, c.positions, variation, n);
    flip_randomly(n, 5);
    orient_normals_mst(index, c.positions, n);
    EXPECT_LE(count_inward(n, c.normals), 2u) << (method ? "robust" : "pca");
  }
}

// A 60° wedge (two faces meeting along the y axis, outward normals 120° apart), every other of
// whose points next to the edge on the lower face carries the upper face's normal, as a PCA row
// holding more of the other face gives it: signed like their upper neighbours it lies 120° from
// their own face's. Marked layered, those signed wrong take their oriented neighbours' mean,
// within 90° of their own face's; no other normal changes.
TEST(NormalsOrient, PointsWhereFacesMeetTakeTheirNeighboursMean) {
  const float h = 0.1f, c30 = std::sqrt(3.0f) / 2;
  const Vec3f n_up{0.5f, 0, c30}, n_down{0.5f, 0, -c30};  // outward; the wedge opens towards -x
  std::vector<Vec3f> positions, normals, truth;
  std::vector<uint8_t> layered;
  for (int t = 1; t <= 8; ++t)
    for (int y = -10; y <= 10; ++y)
      for (int face = 0; face < 2; ++face) {
        const float u = static_cast<float>(t) * h, v = static_cast<float>(y) * h;
        positions.push_back({-c30 * u, v, face == 0 ? 0.5f * u : -0.5f * u});
        truth.push_back(face == 0 ? n_up : n_down);
        const bool blended = face == 1 && t == 1 && y % 2 == 0;
        normals.push_back(blended ? n_up : truth.back());
        layered.push_back(blended);
      }
  const std::size_t n = positions.size();
  flip_randomly(normals, 4);
  const SpatialIndex index(positions);
  const auto orient = [&](std::span<const uint8_t> marks, OrientStats& stats) {
    std::vector<Vec3f> out = normals;
    OrientRegionsOptions regions;
    regions.split_gaps = true;
    regions.layered = marks;
    stats = orient_normals_mst(
        orient_knn_rows([&](std::size_t k, std::span<uint32_t> r) { index_knn_rows(index, k, r); },
                        n, kOrientK),
        positions, out, kOrientK, regions);
    return out;
  };
  OrientStats plain_stats, stats;
  const std::vector<Vec3f> plain = orient({}, plain_stats);
  const std::vector<Vec3f> settled = orient(layered, stats);
  // Each run's frame: outward or inward as a whole (the signs the orientation chose).
  const auto frame = [&](const std::vector<Vec3f>& v) {
    float sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += layered[i] ? 0.0f : dot(v[i], truth[i]);
    return sum > 0 ? 1.0f : -1.0f;
  };
  const float s = frame(settled), s_plain = frame(plain);
  std::size_t plain_wrong = 0, marked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!layered[i]) {
      EXPECT_TRUE(settled[i] == plain[i] || settled[i] == -plain[i]) << i;
      EXPECT_GT(s * dot(settled[i], truth[i]), 0.99f) << i;
      continue;
    }
    ++marked;
    plain_wrong += !(s_plain * dot(plain[i], truth[i]) > 0);
    EXPECT_GT(s * dot(settled[i], truth[i]), 0.1f) << i;  // within 90° of its own face's
    EXPECT_NEAR(squared_norm(settled[i]), 1.0f, 1e-5f) << i;
  }
  EXPECT_GT(stats.settled, 0u);
  EXPECT_LE(stats.settled, marked);
  EXPECT_EQ(plain_stats.settled, 0u);
  EXPECT_GT(plain_wrong, 0u) << marked;
}

TEST(NormalsOrient, EachComponentOutward) {
  // Two unit spheres 5 apart and a small one below: three components, each seeded at its own
  // top-most point.
  SplatCloud a = shape(ShapeKind::kSphere, 3000);
  std::vector<Vec3f> positions, truth;
  for (const Vec3f& shift : {Vec3f{0, 0, 0}, Vec3f{5, 0, 0}}) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      positions.push_back(a.positions[i] + shift);
      truth.push_back(a.normals[i]);
    }
  }
  for (std::size_t i = 0; i < a.size(); i += 10) {
    positions.push_back(a.positions[i] * 0.2f + Vec3f{0, 0, -5});
    truth.push_back(a.normals[i]);
  }
  const SpatialIndex index(positions);
  std::vector<Vec3f> normals = truth;
  flip_randomly(normals, 4);
  const OrientStats stats = orient_normals_mst(index, positions, normals);
  EXPECT_EQ(stats.components, 3u);
  EXPECT_EQ(count_inward(normals, truth), 0u);
}

TEST(NormalsOrient, TinyClouds) {
  const SpatialIndex empty;
  std::vector<Vec3f> none;
  EXPECT_EQ(orient_normals_mst(empty, none, none).components, 0u);

  // One point: its own component, made to point +z.
  std::vector<Vec3f> one = {{1, 2, 3}}, n1 = {{0, 0.6f, -0.8f}};
  OrientStats s1 = orient_normals_mst(SpatialIndex(one), one, n1);
  EXPECT_EQ(s1.components, 1u);
  EXPECT_EQ(s1.flipped, 1u);
  EXPECT_EQ(n1[0], (Vec3f{0, -0.6f, 0.8f}));

  // Two points (fewer than k): one component, the higher point +z, the other consistent.
  std::vector<Vec3f> two = {{0, 0, 0}, {1, 0, 0.1f}}, n2 = {{0, 0, 1}, {0, 0, 1}};
  OrientStats s2 = orient_normals_mst(SpatialIndex(two), two, n2);
  EXPECT_EQ(s2.components, 1u);
  EXPECT_EQ(s2.flipped, 0u);
  EXPECT_EQ(n2[1], (Vec3f{0, 0, 1}));
  n2 = {{0, 0, 1}, {0, 0, -1}};
  orient_normals_mst(SpatialIndex(two), two, n2);
  EXPECT_EQ(n2[0], (Vec3f{0, 0, 1}));
  EXPECT_EQ(n2[1], (Vec3f{0, 0, 1}));

  EXPECT_THROW(orient_normals_mst(SpatialIndex(two), two, n2, 1), std::invalid_argument);
  std::vector<Vec3f> short_normals(1);
  EXPECT_THROW(orient_normals_mst(SpatialIndex(two), two, short_normals), std::invalid_argument);
}

TEST(NormalsOrient, SameResultForOneAndTwoThreads) {
  const SplatCloud c = shape(ShapeKind::kTorus, 20000);
  const SpatialIndex index(c.positions);
  const std::vector<Vec3f> start = pca_normals(index, c.positions);
  std::vector<Vec3f> results[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    results[threads - 1] = start;
    orient_normals_mst(index, c.positions, results[threads - 1]);
  }
  EXPECT_EQ(0,
            std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(Vec3f)));
}

// A noise tail: one point a spacing above a plane, each of its nearest neighbours more along the
// normal than across it (every edge of it runs across a gap, as between a slab's two faces).
// With the gaps kept apart it has no surface of its own and takes the plane's sign (the plane's
// points are seen from above: votes for +z).
TEST(NormalsOrient, NoiseTailFollowsItsSurface) {
  std::vector<Vec3f> positions;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) positions.push_back({x * 1.0f, y * 1.0f, 0.0f});
  positions.push_back({20.3f, 20.4f, 1.2f});
  std::vector<Vec3f> normals(positions.size(), Vec3f{0, 0, 1});
  normals.back() = {0, 0, -1};
  std::vector<float> votes(positions.size(), 1.0f);
  votes.back() = 0;
  OrientRegionsOptions regions;
  regions.split_gaps = true;
  regions.evidence = votes;
  const SpatialIndex index(positions);
  ShrinkableArray rows = orient_knn_rows(
      [&](std::size_t k, std::span<uint32_t> out) { index_knn_rows(index, k, out); },
      positions.size());
  const OrientStats stats =
      orient_normals_mst(std::move(rows), positions, normals, kOrientK, regions);
  EXPECT_EQ(1u, stats.relabelled);
  for (const Vec3f& n : normals) ASSERT_GT(n.z, 0.0f);
}

TEST(NormalsOrient, Viewpoint) {
  std::vector<Vec3f> positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  std::vector<Vec3f> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}};
  // Viewpoint above the line: the first keeps +z, the second flips, and the third flips too
  // (v - p = (-2, 0, 10): dot -2).
  EXPECT_EQ(orient_normals_viewpoint(positions, normals, {0, 0, 10}), 2u);
  EXPECT_EQ(normals[0], (Vec3f{0, 0, 1}));
  EXPECT_EQ(normals[1], (Vec3f{0, 0, 1}));
  EXPECT_EQ(normals[2], (Vec3f{-1, 0, 0}));
  // Exactly perpendicular: kept.
  std::vector<Vec3f> side = {{0, 0, 1}};
  EXPECT_EQ(orient_normals_viewpoint(std::vector<Vec3f>{{0, 0, 0}}, side, {5, 0, 0}), 0u);
  EXPECT_EQ(side[0], (Vec3f{0, 0, 1}));
  // A sphere seen from far away along +x: every normal with x < 0 points away and flips.
  const SplatCloud c = shape(ShapeKind::kSphere, 2000);
  std::vector<Vec3f> n = c.normals;
  std::size_t behind = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    behind += dot(c.normals[i], Vec3f{1e6f, 0, 0} - c.positions[i]) < 0;
  EXPECT_EQ(orient_normals_viewpoint(c.positions, n, {1e6, 0, 0}), behind);
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_GE(dot(n[i], Vec3f{1e6f, 0, 0} - c.positions[i]), 0.0f);
}

}  // namespace
}  // namespace splatkit
