// estimate_normals' orientation on scenes as scans make them: a building with walls and a roof
// slab thicker than nothing but thinner than the kNN reach (both sides sampled), on open ground
// around it. --orient visibility (auto's choice) gets every normal out of the material; the
// visibility votes alone are right where they speak; orient up, sensor and the given normals
// (kKeep, a mesh's faces) do what they say.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "normals/estimate_normals.h"
#include "normals/visibility_votes.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/simd_level.h"
#include "splatkit/splat_cloud.h"

namespace splatkit {
namespace {

struct Scene {
  SplatCloud cloud;
  std::vector<Vec3f> truth;  // out of the material
};

// Samples the rectangle origin + s·a + t·b (s, t in [0, 1]) on a jittered grid of about
// `spacing`, with normal `normal`.
void add_rect(Scene& scene, Vec3f origin, Vec3f a, Vec3f b, Vec3f normal, float spacing,
              DeterministicRng& rng) {
  const int na = std::max(1, static_cast<int>(norm(a) / spacing));
  const int nb = std::max(1, static_cast<int>(norm(b) / spacing));
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) {
      const float s = (i + 0.2f + 0.6f * rng.uniformf()) / static_cast<float>(na);
      const float t = (j + 0.2f + 0.6f * rng.uniformf()) / static_cast<float>(nb);
      scene.cloud.positions.push_back(origin + a * s + b * t);
      scene.truth.push_back(normal);
    }
}

// A box building 6 × 4 × 3 m with walls `thick` thick (outer and inner faces, the tops under the
// roof), a roof slab of the same thickness (top up, ceiling down), on a ground of 14 × 12 m with
// nothing under the building. Spacing 0.1 m.
Scene building(float thick, uint64_t seed = 1) {
  Scene s;
  DeterministicRng rng(seed);
  const float h = 0.1f, W = 6, D = 4, H = 3, t = thick;
  const Vec3f X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
  // Ground: four strips around the footprint [0, W] × [0, D].
  add_rect(s, {-4, -4, 0}, X * (W + 8), Y * 4, Z, h, rng);
  add_rect(s, {-4, D, 0}, X * (W + 8), Y * 4, Z, h, rng);
  add_rect(s, {-4, 0, 0}, X * 4, Y * D, Z, h, rng);
  add_rect(s, {W, 0, 0}, X * 4, Y * D, Z, h, rng);
  // Outer faces.
  add_rect(s, {0, 0, 0}, X * W, Z * H, -Y, h, rng);
  add_rect(s, {0, D, 0}, X * W, Z * H, Y, h, rng);
  add_rect(s, {0, 0, 0}, Y * D, Z * H, -X, h, rng);
  add_rect(s, {W, 0, 0}, Y * D, Z * H, X, h, rng);
  // Inner faces, up to the ceiling.
  add_rect(s, {t, t, 0}, X * (W - 2 * t), Z * (H - t), Y, h, rng);
  add_rect(s, {t, D - t, 0}, X * (W - 2 * t), Z * (H - t), -Y, h, rng);
  add_rect(s, {t, t, 0}, Y * (D - 2 * t), Z * (H - t), X, h, rng);
  add_rect(s, {W - t, t, 0}, Y * (D - 2 * t), Z * (H - t), -X, h, rng);
  // Roof top and ceiling.
  add_rect(s, {0, 0, H}, X * W, Y * D, Z, h, rng);
  add_rect(s, {t, t, H - t}, X * (W - 2 * t), Y * (D - 2 * t), -Z, h, rng);
  return s;
}

double agreement(const SplatCloud& c, const std::vector<Vec3f>& truth) {
  std::size_t ok = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) ok += dot(c.normals[i], truth[i]) > 0;
  return static_cast<double>(ok) / static_cast<double>(truth.size());
}

NormalOptions in_input_order() {
  NormalOptions o;
  o.spatial_order = false;
  o.keep_duplicates = true;
  return o;
}

TEST(NormalsOrientVisibility, ThickWalledBuildingFacesOut) {
  for (float thick : {0.25f, 0.5f}) {
    Scene s = building(thick);
    SplatCloud c = s.cloud;
    const NormalReport r = estimate_normals(c, in_input_order());
    EXPECT_EQ(r.orientation["method"], "visibility");
    EXPECT_GE(agreement(c, s.truth), 0.995) << "walls " << thick << " m thick: " << r.to_json();
  }
}

// Walls and roof 1.6 spacings thick with noise of 0.3 spacing along the normals, as the scan
// test set's noisy city: the k-rows take points of both faces (normals that tilt anywhere) and the
// faces' noise tails come within a spacing of each other. The wider rows give the normals back
// (the report counts them) and the confirmed sheet edges keep the faces apart. Measured: 99.0 %
// out (87.1 % with k-rows alone, 18.7 % of the normals more than 30° off); with the points where
// faces meet taking their oriented neighbours' mean (orient_normals_mst.h) 99.19 % out and 5.3 %
// more than 30° off (4.99 % before: a mean lies between the faces that meet there).
Scene noisy_thin_walls() {
  Scene s = building(0.16f, 3);
  DeterministicRng rng(7);
  for (std::size_t i = 0; i < s.truth.size(); ++i)
    s.cloud.positions[i] += s.truth[i] * (0.03f * static_cast<float>(rng.normal()));
  return s;
}

TEST(NormalsOrientVisibility, NoisyThinWallsFaceOut) {
  const Scene s = noisy_thin_walls();
  SplatCloud c = s.cloud;
  const NormalReport r = estimate_normals(c, in_input_order());
  std::size_t off = 0;  // normals more than 30° from the truth's line
  for (std::size_t i = 0; i < s.truth.size(); ++i)
    off += std::fabs(dot(c.normals[i], s.truth[i])) < 0.866f;
  EXPECT_GT(r.widened_points, s.truth.size() / 10) << r.to_json();
  EXPECT_LT(static_cast<double>(off) / static_cast<double>(s.truth.size()), 0.06) << r.to_json();
  EXPECT_GE(agreement(c, s.truth), 0.98) << r.to_json();
}

// The same walls under --method robust: the fit gives each face its own plane, so the two faces
// of a wall are parallel sheets that join with noise unless the sheet edges at the points whose
// k-rows show no plane are confirmed. Measured: 99.4 % out (76.2 % when only PCA normals were read
// so).
TEST(NormalsOrientVisibility, NoisyThinWallsFaceOutWithRobustNormals) {
  const Scene s = noisy_thin_walls();
  SplatCloud c = s.cloud;
  NormalOptions o = in_input_order();
  o.method = NormalMethod::kRobust;
  const NormalReport r = estimate_normals(c, o);
  EXPECT_EQ(r.orientation["settled"], 0) << r.to_json();  // robust normals keep their creases
  EXPECT_GE(agreement(c, s.truth), 0.98) << r.to_json();
}

TEST(NormalsOrientVisibility, VotesAreRightWhereTheySpeak) {
  Scene s = building(0.3f);
  SplatCloud c = s.cloud;
  NormalOptions o = in_input_order();
  o.orient = NormalOrientation::kNone;
  estimate_normals(c, o);
  VisibilityStats stats;
  const std::vector<float> votes = visibility_votes(c.positions, c.normals, c.radii, {}, &stats);
  std::size_t voted = 0, right = 0, inner_voted = 0;
  for (std::size_t i = 0; i < votes.size(); ++i) {
    if (votes[i] == 0) continue;
    ++voted;
    right += (votes[i] > 0) == (dot(c.normals[i], s.truth[i]) > 0);
  }
  // Inner faces and the ceiling are hidden from every view above the horizon but a few at the
  // grazing bottom of the cap that look in under the open footprint.
  for (std::size_t i = 0; i < votes.size(); ++i) {
    const Vec3f& p = c.positions[i];
    const bool inside = p.x > 0.35f && p.x < 5.65f && p.y > 0.35f && p.y < 3.65f && p.z < 2.6f;
    inner_voted += inside && votes[i] != 0;
  }
  EXPECT_GT(stats.seen, votes.size() / 2);
  EXPECT_GE(static_cast<double>(right) / static_cast<double>(voted), 0.97);
  EXPECT_LT(inner_voted, votes.size() / 50);
}

// A box of 2 m open on its +x side (a closed part cut by a tile's border): the views that look
// in through the opening see the inner side of its faces and vote their outward normals wrong;
// a wall across the opening (where the rest of the part would be) hides them, and the wall's
// own discs vote for nothing. (Counted away from the box's edges, where a disc that reaches past
// the edge shows on the silhouette from either side.)
TEST(NormalsOrientVisibility, WallsHideWhatACutWouldShow) {
  Scene s;
  DeterministicRng rng(3);
  const float h = 0.05f;
  const Vec3f X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
  add_rect(s, {-1, -1, -1}, Y * 2, Z * 2, -X, h, rng);  // the back
  add_rect(s, {-1, -1, -1}, X * 2, Z * 2, -Y, h, rng);
  add_rect(s, {-1, 1, -1}, X * 2, Z * 2, Y, h, rng);
  add_rect(s, {-1, -1, -1}, X * 2, Y * 2, -Z, h, rng);
  add_rect(s, {-1, -1, 1}, X * 2, Y * 2, Z, h, rng);
  const std::size_t n = s.truth.size();
  const std::vector<float> radii(n, 0.06f);
  auto wrong_votes = [&](const VisibilityOptions& o) {
    const std::vector<float> votes = visibility_votes(s.cloud.positions, s.truth, radii, o);
    EXPECT_EQ(votes.size(), n);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3f& p = s.cloud.positions[i];
      const int inner = (std::fabs(p.x) < 0.8f) + (std::fabs(p.y) < 0.8f) + (std::fabs(p.z) < 0.8f);
      wrong += inner == 2 && votes[i] < 0;
    }
    return wrong;
  };
  VisibilityOptions open;
  open.views = 24;
  EXPECT_GT(wrong_votes(open), n / 10);
  VisibilityOptions walled = open;
  walled.walls.push_back({{1.1f, 1.1f, -1.2f}, {0, -2.2f, 0}, 1.2f});
  EXPECT_LE(wrong_votes(walled), n / 1000);  // 4 of 7 900 measured, against over a tenth open
}

TEST(NormalsOrientVisibility, VectorPathVotesAsThePortableOne) {
  // The SSE2 path (discs four at a time, a whole box of pixels per small disc) against the
  // portable one, bit for bit: the building's splats, a few of them 3-30x larger (drawn row by
  // row on both paths), a count that is not a multiple of 4, coarse and fine buffers, and clouds
  // of 1-5 points.
  Scene s = building(0.3f);
  SplatCloud c = s.cloud;
  NormalOptions o = in_input_order();
  o.orient = NormalOrientation::kNone;
  estimate_normals(c, o);
  DeterministicRng rng(5);
  for (std::size_t i = 0; i < c.size(); i += 97)
    c.radii[i] *= static_cast<float>(rng.uniform(3.0, 30.0));
  c.positions.resize(c.size() - c.size() % 4 + 3);
  c.normals.resize(c.positions.size());
  c.radii.resize(c.positions.size());
  std::vector<std::vector<Vec3f>> clouds = {c.positions};
  for (std::size_t m = 1; m <= 5; ++m)
    clouds.emplace_back(c.positions.begin(), c.positions.begin() + m);
  for (const std::vector<Vec3f>& p : clouds)
    for (const std::size_t pixels : {std::size_t{1} << 22, std::size_t{4096}}) {
      VisibilityOptions vo;
      vo.max_pixels = pixels;
      vo.views = 12;
      const std::span<const Vec3f> n(c.normals.data(), p.size());
      const std::span<const float> r(c.radii.data(), p.size());
      std::vector<float> portable;
      {
        ScopedSimdLevel cap(SimdLevel::kPortable);
        portable = visibility_votes(p, n, r, vo);
      }
      const std::vector<float> best = visibility_votes(p, n, r, vo);
      EXPECT_EQ(best, portable) << p.size() << " points, " << pixels << " pixels";
    }
}

TEST(NormalsOrientVisibility, UpAndSensor) {
  Scene s = building(0.3f);
  SplatCloud up = s.cloud;
  NormalOptions o = in_input_order();
  o.orient = NormalOrientation::kUp;
  estimate_normals(up, o);
  for (const Vec3f& n : up.normals) EXPECT_GE(n.z, 0.0f);

  // Each point's sensor 5 m out along its true normal: every normal faces it.
  SplatCloud sensed = s.cloud;
  std::vector<double> sx, sy, sz;
  for (std::size_t i = 0; i < sensed.size(); ++i) {
    const Vec3f q = sensed.positions[i] + s.truth[i] * 5.0f;
    sx.push_back(q.x), sy.push_back(q.y), sz.push_back(q.z);
  }
  sensed.set_extra(ExtraAttribute("sensor_x", ScalarType::kFloat64, sx));
  sensed.set_extra(ExtraAttribute("sensor_y", ScalarType::kFloat64, sy));
  sensed.set_extra(ExtraAttribute("sensor_z", ScalarType::kFloat64, sz));
  NormalOptions a = in_input_order();
  const NormalReport r = estimate_normals(sensed, a);
  EXPECT_EQ(r.orientation["method"], "sensor");
  EXPECT_GE(agreement(sensed, s.truth), 0.999);
}

TEST(NormalsOrientVisibility, KeptNormalsStayAndOrientTheRest) {
  Scene s = building(0.3f);
  SplatCloud c = s.cloud;
  // Input normals on every second point; the rest zero (missing).
  c.normals.assign(c.size(), Vec3f{0, 0, 0});
  for (std::size_t i = 0; i < c.size(); i += 2) c.normals[i] = s.truth[i];
  NormalOptions o = in_input_order();
  o.input_normals = InputNormals::kKeep;
  o.orient = NormalOrientation::kMst;  // the kept normals are the only evidence
  const NormalReport r = estimate_normals(c, o);
  EXPECT_EQ(r.normals_source, "input+estimated");
  EXPECT_EQ(r.given_normals, (c.size() + 1) / 2);
  for (std::size_t i = 0; i < c.size(); i += 2) EXPECT_EQ(c.normals[i], s.truth[i]);
  EXPECT_GE(agreement(c, s.truth), 0.995) << r.to_json();

  // Without kKeep they are estimated again, and the report says the input had them.
  SplatCloud d = s.cloud;
  d.normals = s.truth;
  const NormalReport e = estimate_normals(d, in_input_order());
  EXPECT_EQ(e.normals_source, "estimated");
  EXPECT_EQ(e.input_had_normals, d.size());
}

TEST(NormalsOrientVisibility, MeshNormalsFromFaces) {
  // A tetrahedron wound outward: each vertex normal points away from the centroid.
  SplatCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  c.face_offsets = {0, 3, 6, 9, 12};
  c.face_indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  const NormalReport r = estimate_normals(c, in_input_order());
  EXPECT_EQ(r.normals_source, "faces");
  const Vec3f centroid{0.25f, 0.25f, 0.25f};
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_GT(dot(c.normals[i], c.positions[i] - centroid), 0.0f) << i;
}

TEST(NormalsOrientVisibility, SameForAnyThreadCount) {
  Scene s = building(0.3f);
  std::vector<SplatCloud> out;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    out.push_back(s.cloud);
    estimate_normals(out.back(), in_input_order());
  }
  EXPECT_EQ(out[0].normals, out[1].normals);
  EXPECT_EQ(out[0].radii, out[1].radii);
}

}  // namespace
}  // namespace splatkit
