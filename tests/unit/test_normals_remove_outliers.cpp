// remove_outliers: injected outliers found, true points kept, split_cloud keeps everything else.
// (PCL's filters as the oracle: tests/pcl/outliers_pcl_oracle.cpp.)
#include "normals/remove_outliers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit {
namespace {

struct Injected {
  ShapeOptions shape;
  SplatCloud cloud;
  std::size_t true_points = 0;  // the first true_points are the shape's, the rest injected
  double spacing = 0;           // h: the sampling spacing (random sampling: radius / 1.71)
};

// A scan with 1 % of its points added uniformly in its bounding box.
Injected with_outliers(ShapeKind kind, std::size_t n, double noise, double scan_lines, uint64_t seed) {
  ShapeOptions s;
  s.kind = kind;
  s.points = n;
  s.seed = seed;
  s.noise = noise;
  s.scan_lines = scan_lines;
  s.random = true;
  Injected r{s, make_shape(s), 0, 0};
  r.true_points = r.cloud.size();
  for (std::size_t i = 0; i < r.true_points; ++i) r.spacing += r.cloud.radii[i];
  r.spacing /= 1.71 * static_cast<double>(r.true_points) * (scan_lines > 1 ? std::sqrt(scan_lines) : 1);
  const Bounds b = compute_bounds(r.cloud);
  DeterministicRng rng(seed + 100);
  const std::size_t extra = r.true_points / 100;
  SplatCloud& c = r.cloud;
  for (std::size_t i = 0; i < extra; ++i) {
    c.positions.push_back({static_cast<float>(rng.uniform(b.min.x, b.max.x)),
                           static_cast<float>(rng.uniform(b.min.y, b.max.y)),
                           static_cast<float>(rng.uniform(b.min.z, b.max.z))});
    c.normals.push_back(c.normals.front());
    c.radii.push_back(c.radii.front());
    c.colors.push_back(c.colors.front());
    for (ExtraAttribute& e : c.extras) e.values.push_back(9999);
  }
  return r;
}

// Injected points within 2 spacings of the surface lie in its sampling (and noise) band: no
// distance statistic tells them from surface points (uniform in the box, about 10 % of them at
// 40 000 points). The others must all but never survive; true points must rarely go.
void expect_found(const Injected& in, const OutlierOptions& o, const char* what,
                  std::size_t min_percent_found) {
  const OutlierResult r = find_outliers(in.cloud.positions, o);
  std::size_t lost = 0, found = 0, off = 0, off_found = 0;
  for (std::size_t i = 0; i < in.cloud.size(); ++i) {
    if (i < in.true_points) {
      lost += r.outlier[i];
      continue;
    }
    found += r.outlier[i];
    if (distance_to_shape(in.shape, in.cloud.positions[i]) > 2 * in.spacing) {
      ++off;
      off_found += r.outlier[i];
    }
  }
  const std::size_t injected = in.cloud.size() - in.true_points;
  EXPECT_GE(off_found * 100, off * 95) << what << ": found " << off_found << " of the " << off
                                       << " injected points farther than 2 spacings";
  EXPECT_GE(found * 100, injected * min_percent_found) << what << ": found " << found << " of " << injected;
  EXPECT_LE(lost * 1000, in.true_points * 5) << what << ": lost " << lost << " of " << in.true_points;
  EXPECT_EQ(r.removed, found + lost);
}

// The injected points' share removed, the scan's share removed, and the share removed of the
// injected points farther than off_s (in s) from the scan (s = the square root of the scan's area
// per point: the median distance r8 to the 8th nearest scan point times sqrt(pi / 8), as
// scripts/bench/outliers.sh measures it).
struct Removal {
  double injected = 0, scan = 0, off_surface = 0, near_surface = 0;  // near: within 1.5 s (share)
};

Removal measure(const Injected& in, const std::vector<OutlierOptions>& passes, double off_s = 3) {
  const std::span<const Vec3f> scan(in.cloud.positions.data(), in.true_points);
  const SpatialIndex index(scan);
  std::vector<float> r8(in.true_points);
  index.for_each_knn_block(
      9, [&](std::span<const uint32_t> q, std::span<const uint32_t>, std::span<const float> sq) {
        for (std::size_t r = 0; r < q.size(); ++r) r8[q[r]] = std::sqrt(sq[r * 9 + 8]);
      });
  std::nth_element(r8.begin(), r8.begin() + static_cast<std::ptrdiff_t>(r8.size() / 2), r8.end());
  const double s = r8[r8.size() / 2] * std::sqrt(3.14159265358979 / 8);
  const OutlierPassesResult r = find_outliers(in.cloud.positions, passes);
  std::size_t lost = 0, found = 0, off = 0, off_found = 0, near = 0;
  for (std::size_t i = 0; i < in.cloud.size(); ++i) {
    const bool removed = r.outlier[i] != 0;
    if (i < in.true_points) {
      lost += removed;
      continue;
    }
    found += removed;
    uint32_t nearest;
    float sq;
    index.knn(in.cloud.positions[i], 1, &nearest, &sq);
    const double d = std::sqrt(static_cast<double>(sq)) / s;
    near += d < 1.5;
    if (d > off_s) {
      ++off;
      off_found += removed;
    }
  }
  EXPECT_EQ(r.removed, found + lost);
  const auto injected = static_cast<double>(in.cloud.size() - in.true_points);
  Removal m;
  m.injected = 100.0 * static_cast<double>(found) / injected;
  m.scan = 100.0 * static_cast<double>(lost) / static_cast<double>(in.true_points);
  m.off_surface = 100.0 * static_cast<double>(off_found) / static_cast<double>(off);
  m.near_surface = 100.0 * static_cast<double>(near) / injected;
  std::string name;
  for (const OutlierOptions& o : passes)
    name += std::string(name.empty() ? "" : "+") +
            (o.rule == OutlierRule::kPlane ? "plane:" : "sor:") + std::to_string(o.k) + "," +
            std::to_string(o.sigma).substr(0, 4);
  std::printf(
      "%zu scan points, %s: removed %.1f %% of the injected points (%.1f %% of "
      "those farther than %g s; %.1f %% of them lie within 1.5 s), %.3f %% of the scan\n",
      in.true_points, name.c_str(), m.injected, m.off_surface, off_s, m.near_surface, m.scan);
  return m;
}
Removal measure(const Injected& in, const OutlierOptions& o, double off_s = 3) {
  return measure(in, std::vector<OutlierOptions>{o}, off_s);
}

OutlierOptions sor(std::size_t k, double sigma) {
  OutlierOptions o;
  o.k = k;
  o.sigma = sigma;
  return o;
}

// A dense i.i.d. scan of a sphere, where few injected points land on the surface (2.7 % within
// 1.5 s): the default passes reach the goal, >= 95 % of the injected points and <= 0.5 % of the
// scan (scripts/bench/outliers.sh: 95.9 % at 300 000 points); the former single-pass default
// sor:12,1 does not (the deviation the outliers inflate raises its threshold, in units of s, as
// the scan gets denser).
TEST(NormalsRemoveOutliers, StatisticalOnADenseScan) {
  const Injected in = with_outliers(ShapeKind::kSphere, 400000, 0, 0, 3);
  const Removal m = measure(in, default_statistical_passes(), 5);
  EXPECT_GE(m.off_surface, 99.0);
  EXPECT_GE(m.injected, 95.0);
  EXPECT_LE(m.scan, 0.5);
  const Removal single = measure(in, sor(12, 1), 5);
  EXPECT_LT(single.injected, 95.0);
}

// `--outliers sor` (default_outlier_passes: the statistical passes, then the plane pass) on a
// 100 000-point i.i.d. torus with 1 % uniform outliers: the goal, >= 95 % of them and <= 0.5 % of
// the scan. The statistical passes alone stop near 90 %: the rest lie a spacing or two off the
// surface, where their neighbour distances look like the surface's own sparse spots; their
// distance to the plane of those neighbours does not.
TEST(NormalsRemoveOutliers, DefaultChainOnAnIidTorus) {
  const Injected in = with_outliers(ShapeKind::kTorus, 100000, 0, 0, 1);
  const Removal all = measure(in, default_outlier_passes());
  EXPECT_GE(all.injected, 95.0);
  EXPECT_LE(all.scan, 0.5);
  const Removal statistical = measure(in, default_statistical_passes());
  EXPECT_LT(statistical.injected, 95.0);
  EXPECT_LE(all.scan, statistical.scan + 0.05);  // the plane pass costs the scan next to nothing
}

// The plane pass alone: a point lifted off a plane by a spacing is found, the plane's own points
// are not (nor the points of a single line, which has no plane).
TEST(NormalsRemoveOutliers, PlaneRuleFindsAPointOffThePlane) {
  std::vector<Vec3f> p;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) p.push_back({float(x), float(y), 0.0f});
  p.push_back({9.5f, 9.5f, 1.0f});
  for (int x = 0; x < 20; ++x) p.push_back({float(x), 100.0f, 0.0f});
  OutlierOptions o;
  o.rule = OutlierRule::kPlane;
  o.k = kDefaultPlaneK;
  o.sigma = kDefaultPlaneT;
  const OutlierResult r = find_outliers(p, o);
  EXPECT_EQ(r.removed, 1u);
  EXPECT_EQ(r.outlier[400], 1);
  EXPECT_EQ(r.to_json(o)["rule"], "plane");
}

// On scan lines, noise and creases the defaults remove every injected point off the surface
// (farther than 3 s) and at most 0.5 % of the scan; the injected points within about 1.5 s lie
// in the surface's own sampling and noise band, where no distance rule can tell them (here 9-17 %
// of them: the goal of 95 % in all is out of reach on these scans, by about that share).
TEST(NormalsRemoveOutliers, StatisticalDefaultsRemoveEveryOutlierOffTheSurface) {
  const std::vector<OutlierOptions> sor = default_statistical_passes();
  for (const Removal& m : {measure(with_outliers(ShapeKind::kCadPart, 40000, 0, 4, 1), sor),
                           measure(with_outliers(ShapeKind::kTorus, 40000, 0.002, 0, 2), sor),
                           measure(with_outliers(ShapeKind::kSphere, 40000, 0, 4, 3), sor)}) {
    EXPECT_GE(m.off_surface, 99.0);
    EXPECT_LE(m.scan, 0.5);
    EXPECT_GE(m.injected, 80.0);
  }
}

// Without outliers to inflate the deviation, a single pass at sigma = 1 removes the upper tail
// of the scan's own distances (about 16 %); the default passes keep all but a few per thousand.
TEST(NormalsRemoveOutliers, StatisticalDefaultsKeepACleanScan) {
  for (const Injected& in : {with_outliers(ShapeKind::kCadPart, 40000, 0, 4, 1),
                             with_outliers(ShapeKind::kTorus, 40000, 0.002, 0, 2)}) {
    const std::span<const Vec3f> clean(in.cloud.positions.data(), in.true_points);
    const auto n = static_cast<double>(in.true_points);
    const double chain =
        100.0 * static_cast<double>(find_outliers(clean, default_statistical_passes()).removed) / n;
    const double single = 100.0 * static_cast<double>(find_outliers(clean, sor(12, 1)).removed) / n;
    std::printf("clean scan of %zu points: the defaults remove %.3f %%, sor:12,1 %.2f %%\n",
                in.true_points, chain, single);
    EXPECT_LE(chain, 1.0);
    EXPECT_GE(single, 10.0);
  }
}

// Passes run in turn, each over the points the previous ones kept, with its own statistics: the
// same as running find_outliers again on the survivors, and each point marked with its pass.
TEST(NormalsRemoveOutliers, PassesRunOnThePreviousPassesOutput) {
  const Injected in = with_outliers(ShapeKind::kTorus, 20000, 0.002, 0, 7);
  const std::vector<OutlierOptions> chain = {sor(12, 3), sor(6, 3.5)};
  const OutlierPassesResult r = find_outliers(in.cloud.positions, chain);
  const OutlierResult first = find_outliers(in.cloud.positions, chain[0]);
  std::vector<Vec3f> kept;
  std::vector<std::size_t> kept_ids;
  for (std::size_t i = 0; i < in.cloud.size(); ++i)
    if (!first.outlier[i]) kept.push_back(in.cloud.positions[i]), kept_ids.push_back(i);
  const OutlierResult second = find_outliers(kept, chain[1]);
  ASSERT_EQ(r.passes.size(), 2u);
  EXPECT_EQ(r.passes[0].removed, first.removed);
  EXPECT_EQ(r.passes[1].removed, second.removed);
  EXPECT_DOUBLE_EQ(r.passes[1].threshold, second.threshold);
  EXPECT_LT(r.passes[1].stddev, r.passes[0].stddev);  // the far outliers no longer inflate it
  EXPECT_GT(second.removed, 0u);
  std::vector<uint8_t> expected(in.cloud.size(), 0);
  for (std::size_t i = 0; i < in.cloud.size(); ++i) expected[i] = first.outlier[i];
  for (std::size_t j = 0; j < kept.size(); ++j)
    if (second.outlier[j]) expected[kept_ids[j]] = 2;
  EXPECT_EQ(r.outlier, expected);
  EXPECT_EQ(r.removed, first.removed + second.removed);
  const nlohmann::json j = r.to_json(chain);
  EXPECT_EQ(j["removed"], r.removed);
  EXPECT_EQ(j["passes"][1]["removed"], second.removed);
  EXPECT_EQ(j["passes"][1]["k"], 6);
}

// The default passes against the former single-pass default on scan lines and noise: about as
// many injected points or more (here 85.0 against 86.0 % on the scan lines, 83.8 against
// 82.5 % with noise; over the bench's 11 scans 3 points more on average, better or equal on 10).
TEST(NormalsRemoveOutliers, DefaultPassesAgainstTheSinglePass) {
  for (const Injected& in : {with_outliers(ShapeKind::kCadPart, 40000, 0, 4, 1),
                             with_outliers(ShapeKind::kTorus, 40000, 0.002, 0, 2)}) {
    const Removal one = measure(in, sor(12, 1));
    const Removal two = measure(in, default_statistical_passes());
    EXPECT_GE(two.injected, one.injected - 2.0);
  }
}

TEST(NormalsRemoveOutliers, RadiusDefaultsFindInjectedOutliers) {
  OutlierOptions radius;
  radius.rule = OutlierRule::kRadius;  // automatic R, N = 6
  expect_found(with_outliers(ShapeKind::kCadPart, 40000, 0, 0, 4), radius, "cad, random", 75);
  expect_found(with_outliers(ShapeKind::kTorus, 40000, 0.002, 0, 5), radius, "torus, noise", 75);
}

TEST(NormalsRemoveOutliers, RadiusCountsNeighboursWithinR) {
  // Points on a line 1 apart, and one 10 away: within R = 1.5 the ends have 1 neighbour, the
  // middle ones 2, the far point none.
  const std::vector<Vec3f> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {13, 0, 0}};
  OutlierOptions o;
  o.rule = OutlierRule::kRadius;
  o.radius = 1.5;
  o.min_neighbors = 2;
  EXPECT_EQ(find_outliers(p, o).outlier, (std::vector<uint8_t>{1, 0, 0, 1, 1}));
  o.min_neighbors = 1;
  EXPECT_EQ(find_outliers(p, o).outlier, (std::vector<uint8_t>{0, 0, 0, 0, 1}));
}

TEST(NormalsRemoveOutliers, StatisticalThresholdIsMeanPlusSigmaStddev) {
  // k = 1: d_i is the distance to the nearest point: 1, 1, 1, 1, 10.
  const std::vector<Vec3f> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {13, 0, 0}};
  OutlierOptions o;
  o.k = 1;
  o.sigma = 1;
  const OutlierResult r = find_outliers(p, o);
  EXPECT_DOUBLE_EQ(r.mean, 2.8);
  EXPECT_NEAR(r.stddev, 4.0249223594996213, 1e-12);  // sample std of {1,1,1,1,10}
  EXPECT_EQ(r.outlier, (std::vector<uint8_t>{0, 0, 0, 0, 1}));
  o.k = 5;  // as many neighbours as the cloud has others: nothing is judged
  EXPECT_EQ(find_outliers(p, o).removed, 0u);
}

TEST(NormalsRemoveOutliers, SplitCloudMovesEveryAttributeAndRenumbersFaces) {
  SplatCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  c.radii = {0.1f, 0.2f, 0.3f, 0.4f};
  c.colors = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}};
  c.extras = {{"id", ScalarType::kUInt32, {10, 11, 12, 13}}};
  c.face_offsets = {0, 3, 6};
  c.face_indices = {0, 2, 3, 0, 1, 2};
  const SplatCloud out = split_cloud(c, {0, 1, 0, 0});
  EXPECT_EQ(c.positions, (std::vector<Vec3f>{{0, 0, 0}, {2, 0, 0}, {3, 0, 0}}));
  EXPECT_EQ(c.radii, (std::vector<float>{0.1f, 0.3f, 0.4f}));
  EXPECT_EQ(c.extras[0].values.doubles(), (std::vector<double>{10, 12, 13}));
  EXPECT_EQ(c.face_offsets, (std::vector<uint32_t>{0, 3}));
  EXPECT_EQ(c.face_indices, (std::vector<uint32_t>{0, 1, 2}));
  c.check_consistent();
  EXPECT_EQ(out.positions, (std::vector<Vec3f>{{1, 0, 0}}));
  EXPECT_EQ(out.colors.size(), 1u);
  EXPECT_EQ(out.extras[0].values.doubles(), (std::vector<double>{11}));
  out.check_consistent();
}

}  // namespace
}  // namespace splatkit
