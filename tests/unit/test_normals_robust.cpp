// robust_normals: exact plane normals next to a 90° crease where PCA blends, the CAD part's
// crease band, noisy clouds switching to wider rows, byte-identical results for 1 and 2 threads,
// no NaN on degenerate input, and the pruned candidate search giving bit for bit what the plain
// search over every candidate gives.
#include "normals/robust_normals.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "normals/fit_plane.h"
#include "normals/neighborhood_pca.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/pca_normal.h"
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

// The robust fit as first written: the scale statistic of every candidate selected in full, no
// pruning. robust_normals prunes the candidates it can prove irrelevant and must match this bit
// for bit (constants as in robust_normals.cpp).
namespace reference {

// Point i's robust normal from its kNN row; false when the fit fails.
bool fit(std::span<const Vec3f> positions, uint32_t i, std::span<const uint32_t> ids,
         const RobustNormalOptions& options, Vec3f& normal) {
  std::vector<Vec3f> local;
  for (const uint32_t j : ids)
    if (j != SpatialIndex::kNone) local.push_back(positions[j] - positions[i]);
  const std::size_t m = local.size();
  if (m < 6) return false;
  local[0] = Vec3f{0, 0, 0};
  DeterministicRng rng(options.seed, i);
  std::vector<Plane> planes;
  for (std::size_t attempt = 0;
       attempt < 4 * options.candidates && planes.size() < options.candidates; ++attempt) {
    const uint64_t a = (attempt % 2 == 0) ? 0 : rng.next() % m;
    const uint64_t b = rng.next() % m, c = rng.next() % m;
    if (a == b || a == c || b == c) continue;
    Plane p;
    if (triplet_plane(local[a], local[b], local[c], 0.01f, p)) planes.push_back(p);
  }
  if (planes.empty()) return false;
  float radius2 = 0;
  for (const Vec3f& q : local) radius2 = std::max(radius2, squared_norm(q));
  const float floor_band = static_cast<float>(1e-4) * std::sqrt(radius2);
  const std::size_t rank = std::max<std::size_t>(3, static_cast<std::size_t>(m / 3.0));
  const auto band_per_stat = static_cast<float>(2.5 * (1.0 / 0.4307));
  float best_stat = INFINITY;
  std::vector<float> residuals(m);
  std::vector<Plane> kept;
  for (const Plane& p : planes) {
    for (std::size_t j = 0; j < m; ++j) residuals[j] = std::fabs(dot(p.n, local[j]) - p.offset);
    std::nth_element(residuals.begin(), residuals.begin() + (rank - 1), residuals.end());
    const float stat = residuals[rank - 1];
    const float band = std::max(floor_band, band_per_stat * stat);
    if (!(std::fabs(p.offset) <= band)) continue;
    if (inliers_span_plane(local, p, band, 0.15)) best_stat = std::min(best_stat, stat);
    kept.push_back(p);
  }
  if (kept.empty() || best_stat == INFINITY) return false;
  const float h = std::max(floor_band, band_per_stat * best_stat);
  const float inv_h2 = 1.0f / (h * h);
  float best_score = -1;
  const Plane* best = nullptr;
  for (const Plane& p : kept) {
    if (!(std::fabs(p.offset) <= h)) continue;
    float score = 0;
    for (const Vec3f& q : local) {
      const float r = dot(p.n, q) - p.offset;
      score += std::max(0.0f, 1.0f - r * r * inv_h2);
    }
    if (score > best_score) best_score = score, best = &p;
  }
  if (!best) return false;
  Plane plane = *best;
  for (int pass = 0; pass < 2; ++pass) {
    Plane next;
    if (!refit_plane(local, plane, h, next)) break;
    plane = next;
  }
  if (!(std::fabs(plane.offset) <= 2 * h) || !inliers_span_plane(local, plane, h, 0.15))
    return false;
  normal = canonical_sign(plane.n);
  return true;
}

}  // namespace reference

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

// robust_normals on a 20k-point CAD part with the given noise, against the unpruned reference fit
// run on the same points with the same rows: the same normals bit for bit, the same count.
void expect_pruned_search_matches_the_full_search(double noise) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kCadPart;
  shape.points = 20000;
  shape.noise = noise;
  const SplatCloud cad = make_shape(shape);
  const SpatialIndex index(cad.positions);
  const PcaPass pass = pca_pass(index, cad.positions, 16);
  std::vector<Vec3f> normals = pass.normals;
  const RobustNormalStats stats = robust_normals(index, cad.positions, pass.variation, normals);
  ASSERT_EQ(stats.noisy, noise > 0);
  ASSERT_GT(stats.refined, 500u);
  std::vector<Vec3f> expected = pass.normals;
  const RobustNormalOptions options;
  std::vector<uint32_t> ids(stats.k);
  std::size_t refined = 0;
  for (uint32_t i = 0; i < cad.size(); ++i) {
    if (!stats.noisy) {
      // Clean: the refined points are those above the variation threshold, refit over k-rows.
      if (!(pass.variation[i] > static_cast<float>(stats.threshold))) continue;
      const std::size_t m = index.knn(cad.positions[i], stats.k, ids.data(), nullptr);
      refined += reference::fit(cad.positions, i, std::span(ids).first(m), options, expected[i]);
      continue;
    }
    // Noisy: every point's wide row decides; rows above the wide threshold get the robust fit.
    if (pass.variation[i] < 0) continue;
    index.knn(cad.positions[i], stats.k, ids.data(), nullptr);
    const PcaNormal pca = neighborhood_pca(cad.positions, ids);
    if (surface_variation(pca) > static_cast<float>(stats.wide_threshold))
      refined += reference::fit(cad.positions, i, ids, options, expected[i]);
    else if (!pca.degenerate)
      expected[i] = pca.normal;
  }
  EXPECT_EQ(refined, stats.refined);
  EXPECT_EQ(0, std::memcmp(normals.data(), expected.data(), normals.size() * sizeof(Vec3f)));
}

TEST(NormalsRobust, PrunedSearchMatchesTheFullSearchBitForBit) {
  expect_pruned_search_matches_the_full_search(0);
}

TEST(NormalsRobust, PrunedSearchMatchesTheFullSearchBitForBitWhenNoisy) {
  expect_pruned_search_matches_the_full_search(0.004);  // ~0.6 spacings, as 0.00125 at 200k
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
