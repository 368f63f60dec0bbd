// neighborhood_pca: analytic normals, canonical sign, degenerate sets flagged, never NaN.
#include "normals/neighborhood_pca.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace splatkit {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

std::vector<uint32_t> iota(std::size_t n) {
  std::vector<uint32_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<uint32_t>(i);
  return v;
}

TEST(NormalsNeighborhoodPca, TiltedPlaneFarFromOrigin) {
  // Plane through (1000, -500, 20) with normal (1, 2, 2)/3, spanned by (2,-1,0)/√5 and
  // (2,4,-5)/√45.
  const Vec3f o{1000, -500, 20};
  const Vec3f u = normalized({2, -1, 0}), v = normalized({2, 4, -5});
  std::vector<Vec3f> pts;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) pts.push_back(o + u * (0.01f * i) + v * (0.013f * j));
  PcaNormal pca = neighborhood_pca(pts, iota(pts.size()));
  EXPECT_FALSE(pca.degenerate);
  EXPECT_NEAR(pca.normal.x, 1.0f / 3, 2e-3);  // float positions near 1000: ~1e-4 quantisation
  EXPECT_NEAR(pca.normal.y, 2.0f / 3, 2e-3);
  EXPECT_NEAR(pca.normal.z, 2.0f / 3, 2e-3);
}

TEST(NormalsNeighborhoodPca, CanonicalSign) {
  EXPECT_EQ(canonical_sign({0, 0, -1}), (Vec3f{0, 0, 1}));
  EXPECT_EQ(canonical_sign({0.6f, -0.8f, 0}), (Vec3f{-0.6f, 0.8f, 0}));
  EXPECT_EQ(canonical_sign({-0.6f, 0.8f, 0}), (Vec3f{-0.6f, 0.8f, 0}));
  std::vector<Vec3f> pts = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}, {1, 1, 5}};
  EXPECT_EQ(neighborhood_pca(pts, iota(4)).normal, (Vec3f{0, 0, 1}));
}

TEST(NormalsNeighborhoodPca, SkipsUnusedSlots) {
  std::vector<Vec3f> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<uint32_t> ids = {0, 1, 2, kNone, kNone};
  PcaNormal pca = neighborhood_pca(pts, ids);
  EXPECT_FALSE(pca.degenerate);
  EXPECT_EQ(pca.normal, (Vec3f{0, 0, 1}));
}

TEST(NormalsNeighborhoodPca, DegenerateSetsAreFlaggedNeverNaN) {
  std::vector<Vec3f> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {1, 1, 1}};
  PcaNormal l = neighborhood_pca(line, iota(line.size()));
  EXPECT_TRUE(l.degenerate);
  EXPECT_NEAR(std::fabs(dot(l.axis, normalized({1, 1, 1}))), 1.0f, 1e-6);
  EXPECT_NEAR(norm(l.normal), 1.0f, 1e-6);

  std::vector<Vec3f> two = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1, 0, 0}};
  EXPECT_TRUE(neighborhood_pca(two, iota(4)).degenerate);

  std::vector<Vec3f> same(7, Vec3f{3, 4, 5});
  PcaNormal s = neighborhood_pca(same, iota(7));
  EXPECT_TRUE(s.degenerate);
  EXPECT_EQ(s.normal, (Vec3f{0, 0, 1}));

  PcaNormal one = neighborhood_pca(same, std::vector<uint32_t>{2});
  EXPECT_TRUE(one.degenerate);
  EXPECT_EQ(one.normal, (Vec3f{0, 0, 1}));
}

}  // namespace
}  // namespace splatkit
