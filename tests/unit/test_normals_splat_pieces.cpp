// estimate_normals in pieces (splat_pieces.h) against the whole-cloud run: the same bytes for
// every normal and radius, on clouds as scanners make them (i.i.d. random, scan lines with noise,
// duplicates, far outliers, a 100x density jump, large coordinates), with circles and ellipses,
// the cover and mean-kNN rules, and pieces small enough that halos matter.
#include "normals/estimate_normals.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "splatkit/deterministic_rng.h"
#include "splatkit/error.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit {
namespace {

SplatCloud shape(ShapeKind kind, std::size_t n, double scan_lines, double noise) {
  ShapeOptions s;
  s.kind = kind;
  s.points = n;
  s.random = true;
  s.scan_lines = scan_lines;
  s.noise = noise;
  s.seed = 7;
  SplatCloud c = make_shape(s);
  c.normals.clear();
  c.radii.clear();
  c.colors.clear();  // positions only: the tests below add points
  c.extras.clear();
  return c;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Runs the whole cloud and pieces of `piece` points; expects the same splats and counts.
void expect_same_in_pieces(const SplatCloud& input, NormalOptions o, std::size_t piece,
                           const std::string& what) {
  SplatCloud whole = input, pieces = input;
  const NormalReport a = estimate_normals(whole, o);
  o.piece_points = piece;
  const NormalReport b = estimate_normals(pieces, o);
  ASSERT_FALSE(b.pieces.is_null()) << what;
  EXPECT_GT(b.pieces["pieces"].get<std::size_t>(), 3u) << what;
  EXPECT_TRUE(same_bytes(whole.positions, pieces.positions)) << what;
  EXPECT_TRUE(same_bytes(whole.normals, pieces.normals)) << what;
  EXPECT_TRUE(same_bytes(whole.radii, pieces.radii)) << what;
  EXPECT_TRUE(same_bytes(whole.axes, pieces.axes)) << what;
  EXPECT_TRUE(same_bytes(whole.minor_radii, pieces.minor_radii)) << what;
  EXPECT_EQ(a.degenerate_points, b.degenerate_points) << what;
  EXPECT_EQ(a.unresolved_points, b.unresolved_points) << what;
  EXPECT_EQ(a.refitted_points, b.refitted_points) << what;
  EXPECT_EQ(a.isolated_points, b.isolated_points) << what;
  EXPECT_EQ(a.bounded_radii, b.bounded_radii) << what;
  EXPECT_EQ(a.flipped_points, b.flipped_points) << what;
}

TEST(SplatPieces, RandomTorusGivesTheWholeCloudsSplats) {
  NormalOptions o;
  o.spatial_order = true;
  expect_same_in_pieces(shape(ShapeKind::kTorus, 60000, 0, 0), o, 8000, "torus");
}

TEST(SplatPieces, NoisyScanLinesWithDuplicatesAndOutliers) {
  SplatCloud c = shape(ShapeKind::kCadPart, 40000, 8, 0.001);
  DeterministicRng rng{3};
  const std::size_t n = c.positions.size();
  for (std::size_t i = 0; i < n / 50; ++i)  // 2 % duplicates
    c.positions.push_back(c.positions[rng.next() % n]);
  for (std::size_t i = 0; i < n / 100; ++i)  // 1 % outliers in and around the box
    c.positions.push_back({4 * rng.uniformf() - 2, 4 * rng.uniformf() - 2, 4 * rng.uniformf() - 2});
  c.positions.push_back({40, 40, 40});  // one far away
  NormalOptions o;
  expect_same_in_pieces(c, o, 5000, "cad scan lines, pca cover");
  o.ellipses = true;
  o.orient = NormalOrientation::kNone;
  expect_same_in_pieces(c, o, 5000, "cad scan lines, ellipses");
  o.ellipses = false;
  o.radius_rule = RadiusRule::kMeanKnn;
  o.keep_duplicates = true;
  expect_same_in_pieces(c, o, 5000, "cad scan lines, mean-knn, duplicates kept");
}

TEST(SplatPieces, DensityJumpAndLargeCoordinates) {
  // A plane sampled 100x denser on one half, far from the origin (float spacing ~1e-3 at 1e4).
  DeterministicRng rng{5};
  SplatCloud c;
  for (int i = 0; i < 50000; ++i) {
    const float x = rng.uniformf(), y = rng.uniformf();
    if (x < 0.5f || rng.uniformf() < 0.01f)
      c.positions.push_back({10000.0f + 100 * x, -20000.0f + 100 * y, 300.0f + 0.5f * x * y});
  }
  NormalOptions o;
  o.k = 10;
  o.radius_k = 4;
  expect_same_in_pieces(c, o, 4000, "density jump");
  // Rows shorter than the MST orientation's: its kNN rows come from a pass over the pieces of
  // their own instead of the heads of the normals' rows.
  o.k = 8;
  expect_same_in_pieces(c, o, 4000, "density jump, short rows");
}

TEST(SplatPieces, RefusesTheRobustMethodAndFittedCentres) {
  SplatCloud c = shape(ShapeKind::kSphere, 2000, 0, 0);
  NormalOptions o;
  o.piece_points = 500;
  o.method = NormalMethod::kRobust;
  EXPECT_THROW(estimate_normals(c, o), Error);
  o.method = NormalMethod::kPca;
  o.fit_centres = true;
  EXPECT_THROW(estimate_normals(c, o), Error);
}

}  // namespace
}  // namespace splatkit
