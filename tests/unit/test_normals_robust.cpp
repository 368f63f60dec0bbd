// robust_normals: exact plane normals next to a 90° crease where PCA blends, the CAD part's
// crease band, noisy clouds switching to wider rows, byte-identical results for 1 and 2 threads,
// and no NaN on degenerate input.
#include "normals/robust_normals.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "normals/neighborhood_pca.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit {
namespace {

constexpr float kDeg = 3.14159265f / 180;

struct PcaPass {
  std::vector<Vec3f> normals;
  std::vector<float> variation;
};

// What the pipeline does before the robust step: PCA over k-rows, degenerate rows marked -1.
PcaPass pca_pass(const SpatialIndex& index, std::span<const Vec3f> positions, std::size_t k) {
  const std::size_t n = positions.size();
  std::vector<uint32_t> rows(n * k);
  index.knn_all(k, rows);
  PcaPass out{std::vector<Vec3f>(n), std::vector<float>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    const PcaNormal pca = neighborhood_pca(positions, std::span(rows).subspan(i * k, k));
    out.normals[i] = pca.normal;
    out.variation[i] = pca.degenerate ? -1.0f : static_cast<float>(surface_variation(pca));
  }
  return out;
}

float angle_up_to_sign(const Vec3f& a, const Vec3f& b) {
  return std::acos(std::min(1.0f, std::fabs(dot(a, b))));
}

// Two half-planes meeting at 90° along the y axis: z = 0 for x < 0 (normal +z) and x = 0 for
// z > 0 (normal +x), a square grid of spacing h on each, no point on the crease line itself.
struct Roof {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> truth;
  std::vector<float> crease_distance;
};

Roof make_roof(int cells, float h) {
  Roof r;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells / 2; ++i) {
      const float y = static_cast<float>(j) * h, d = (static_cast<float>(i) + 0.5f) * h;
      r.positions.push_back({-d, y, 0}), r.truth.push_back({0, 0, 1});
      r.positions.push_back({0, y, d}), r.truth.push_back({1, 0, 0});
      r.crease_distance.push_back(d), r.crease_distance.push_back(d);
    }
  }
  return r;
}

TEST(NormalsRobust, SurfaceVariation) {
  PcaNormal pca;
  pca.eigenvalues[0] = 1, pca.eigenvalues[1] = 2, pca.eigenvalues[2] = 3;
  EXPECT_DOUBLE_EQ(surface_variation(pca), 1.0 / 6.0);
  pca.eigenvalues[0] = pca.eigenvalues[1] = pca.eigenvalues[2] = 0;
  EXPECT_EQ(surface_variation(pca), 0.0);
}

TEST(NormalsRobust, RoofGetsExactPlaneNormalsWherePcaBlends) {
  const float h = 0.01f;
  const Roof roof = make_roof(40, h);
  const SpatialIndex index(roof.positions);
  PcaPass pass = pca_pass(index, roof.positions, 16);
  std::size_t pca_blended = 0;
  for (std::size_t i = 0; i < roof.positions.size(); ++i)
    if (roof.crease_distance[i] < 2 * h &&
        angle_up_to_sign(pass.normals[i], roof.truth[i]) > 10 * kDeg)
      ++pca_blended;
  EXPECT_GT(pca_blended, 40u);  // PCA's blend: the rows at 0.5 h and 1.5 h from the crease

  const RobustNormalStats stats =
      robust_normals(index, roof.positions, pass.variation, pass.normals);
  EXPECT_GT(stats.candidates, 0u);
  EXPECT_FALSE(stats.noisy);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < roof.positions.size(); ++i) {
    if (roof.crease_distance[i] < h) continue;
    // The grid is exact, so the refit over the inliers is the exact plane up to float rounding.
    EXPECT_LT(angle_up_to_sign(pass.normals[i], roof.truth[i]), 0.01f * kDeg) << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(NormalsRobust, CadPartCreaseBand) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kCadPart;
  shape.points = 30000;
  const SplatCloud cad = make_shape(shape);
  const SpatialIndex index(cad.positions);
  PcaPass pass = pca_pass(index, cad.positions, 16);
  const float h = std::sqrt(25.0f / 30000);  // ~ the sampling step of this part
  auto within10_near_crease = [&](const std::vector<Vec3f>& normals) {
    std::size_t near = 0, good = 0;
    for (std::size_t i = 0; i < cad.size(); ++i) {
      if (distance_to_crease(ShapeKind::kCadPart, cad.positions[i]) >= 2 * h) continue;
      ++near;
      good += angle_up_to_sign(normals[i], cad.normals[i]) <= 10 * kDeg;
    }
    return static_cast<double>(good) / static_cast<double>(near);
  };
  const double pca = within10_near_crease(pass.normals);
  robust_normals(index, cad.positions, pass.variation, pass.normals);
  const double robust = within10_near_crease(pass.normals);
  EXPECT_LT(pca, 0.5);
  EXPECT_GT(robust, 0.9);
}

TEST(NormalsRobust, NoisyPlaneUsesWiderRowsAndBeatsPca) {
  // A plane with noise of half the spacing: PCA over 16 points is off by ~8° RMS.
  const float h = 0.01f;
  DeterministicRng rng(3);
  std::vector<Vec3f> positions;
  for (int j = 0; j < 60; ++j)
    for (int i = 0; i < 60; ++i)
      positions.push_back({static_cast<float>(i) * h, static_cast<float>(j) * h,
                           static_cast<float>(0.5 * h * rng.normal())});
  const SpatialIndex index(positions);
  PcaPass pass = pca_pass(index, positions, 16);
  auto rms = [&](const std::vector<Vec3f>& normals) {
    double sum = 0;
    for (const Vec3f& n : normals) sum += std::pow(angle_up_to_sign(n, {0, 0, 1}), 2);
    return std::sqrt(sum / static_cast<double>(normals.size()));
  };
  const double before = rms(pass.normals);
  const RobustNormalStats stats = robust_normals(index, positions, pass.variation, pass.normals);
  EXPECT_TRUE(stats.noisy);
  EXPECT_GT(stats.k, 32u);
  EXPECT_LT(rms(pass.normals), 0.6 * before);
}

TEST(NormalsRobust, SameResultForOneAndTwoThreads) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kCadPart;
  shape.points = 20000;
  shape.noise = 0.00125;
  const SplatCloud cad = make_shape(shape);
  const SpatialIndex index(cad.positions);
  const PcaPass pass = pca_pass(index, cad.positions, 16);
  std::vector<Vec3f> results[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    results[threads - 1] = pass.normals;
    robust_normals(index, cad.positions, pass.variation, results[threads - 1]);
  }
  ASSERT_EQ(results[0].size(), results[1].size());
  EXPECT_EQ(0,
            std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(Vec3f)));
}

TEST(NormalsRobust, NeverNaNOnDegenerateInput) {
  std::vector<std::vector<Vec3f>> clouds = {
      {},                                            // empty
      {{1, 2, 3}},                                   // one point
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}},  // a short line
      std::vector<Vec3f>(50, Vec3f{1, 1, 1}),        // one position, many times
  };
  std::vector<Vec3f> line, clumps;
  for (int i = 0; i < 200; ++i) line.push_back({static_cast<float>(i) * 0.1f, 0, 0});
  for (int i = 0; i < 300; ++i)  // three clumps of exact duplicates forming a triangle
    clumps.push_back({static_cast<float>(i % 3), static_cast<float>(i % 3 == 1), 0});
  clouds.push_back(line);
  clouds.push_back(clumps);
  for (const std::vector<Vec3f>& positions : clouds) {
    const SpatialIndex index(positions);
    // Force points through both paths, degenerate or not: all variations high (a "noisy" cloud:
    // every point refit over wide rows), and one point in three high over a planar median (the
    // robust fit for those only).
    for (int mode = 0; mode < 2; ++mode) {
      PcaPass pass = pca_pass(index, positions, 16);
      std::vector<float> variation(positions.size(), 0.3f);
      for (std::size_t i = 0; mode == 1 && i < variation.size(); ++i)
        if (i % 3 != 0) variation[i] = 0;
      robust_normals(index, positions, variation, pass.normals);
      for (const Vec3f& n : pass.normals) {
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
        EXPECT_NEAR(norm(n), 1.0f, 1e-5f);
      }
    }
  }
}

}  // namespace
}  // namespace splatkit
