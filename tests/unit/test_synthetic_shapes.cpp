// make_shape and its helpers against analytic answers: points on the surface, exact outward
// normals, labels on the right patch, counts, determinism, noise statistics, radii that match
// the 5-NN distance and cover the surface, distances to creases.
#include "splatkit/synthetic_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "formats/write_cloud.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

constexpr double kPi = std::numbers::pi;
const ShapeKind kAllKinds[] = {ShapeKind::kSphere, ShapeKind::kTorus, ShapeKind::kCadPart,
                               ShapeKind::kTwoSpheres, ShapeKind::kCube};

ShapeOptions shape(ShapeKind kind, std::size_t points, bool random = false) {
  ShapeOptions o;
  o.kind = kind;
  o.points = points;
  o.random = random;
  return o;
}

std::vector<double> patch_ids(const SplatCloud& c) {
  const ExtraAttribute* e = c.find_extra("patch_id");
  EXPECT_NE(e, nullptr);
  return e ? e->values.doubles() : std::vector<double>{};
}

// Total area of each shape, worked out by hand (independent of the library's own sums).
double cad_area() {
  const double top_end = 1.5 - 1.2 / std::sqrt(3.0);
  const double bevel = 1.2 / std::sin(kPi / 3);
  const double hole = kPi * 0.25 * 0.25, boss = kPi * 0.4 * 0.4;
  return (6 - hole) + (2 * (top_end + 1.5) - boss - hole) + 2.4 + 2 * bevel +
         2 * (3 + top_end + 1.5) / 2 * 1.2 + 2 * kPi * 0.4 * 0.5 + boss + 2 * kPi * 0.25 * 1.2;
}

double total_area(const ShapeOptions& o) {
  switch (o.kind) {
    case ShapeKind::kSphere:
      return 4 * kPi;
    case ShapeKind::kTorus:
      return 4 * kPi * kPi * 1.0 * 0.35;
    case ShapeKind::kCadPart:
      return cad_area();
    case ShapeKind::kTwoSpheres:
      return o.keep_inside ? 8 * kPi : 2 * 2 * kPi * 1.6;
    case ShapeKind::kCube:
      return 24;
  }
  return 0;
}

// The expected outward normal of a point labelled `patch`, and its distance to that patch's
// carrier surface (plane, cylinder, sphere, torus), from the documented geometry alone.
struct Expected {
  Vec3f normal;
  double off_surface;  // distance from the carrier surface
  bool in_region;      // inside the patch's extent (face polygon, cylinder height, ...)
};

Expected expect_cad(uint32_t patch, const Vec3f& p) {
  const double top_end = 1.5 - 1.2 / std::sqrt(3.0);
  const double s = std::sqrt(3.0) / 2;
  const double boss_r = std::hypot(p.x + 0.7, p.y), hole_r = std::hypot(p.x - 0.2, p.y);
  const bool in_y = std::abs(p.y) <= 1 + 1e-6;
  const double e = 1e-6;
  switch (patch) {
    case 0:
      return {{0, 0, -1}, std::abs(p.z), in_y && std::abs(p.x) <= 1.5 + e && hole_r >= 0.25 - e};
    case 1:
      return {
          {0, 0, 1},
          std::abs(p.z - 1.2),
          in_y && p.x >= -1.5 - e && p.x <= top_end + e && hole_r >= 0.25 - e && boss_r >= 0.4 - e};
    case 2:
      return {{-1, 0, 0}, std::abs(p.x + 1.5), in_y && p.z >= -e && p.z <= 1.2 + e};
    case 3:
      return {{float(s), 0, 0.5f},
              std::abs((p.x - 1.5) * s + p.z * 0.5),
              in_y && p.z >= -e && p.z <= 1.2 + e};
    case 4:
    case 5: {
      const double y = patch == 4 ? -1 : 1;
      // Inside the trapezoid (-1.5, 0) (1.5, 0) (top_end, 1.2) (-1.5, 1.2).
      const bool inside =
          p.x >= -1.5 - e && p.z >= -e && p.z <= 1.2 + e && (p.x - 1.5) * s + p.z * 0.5 <= e;
      return {{0, float(y), 0}, std::abs(p.y - y), inside};
    }
    case 6:
      return {{float((p.x + 0.7) / boss_r), float(p.y / boss_r), 0},
              std::abs(boss_r - 0.4),
              p.z >= 1.2 - e && p.z <= 1.7 + e};
    case 7:
      return {{0, 0, 1}, std::abs(p.z - 1.7), boss_r <= 0.4 + e};
    case 8:
      return {{float(-(p.x - 0.2) / hole_r), float(-p.y / hole_r), 0},
              std::abs(hole_r - 0.25),
              p.z >= -e && p.z <= 1.2 + e};
  }
  return {{0, 0, 0}, 1e9, false};
}

Expected expect(const ShapeOptions& o, uint32_t patch, const Vec3f& p) {
  switch (o.kind) {
    case ShapeKind::kSphere:
      return {p / norm(p), std::abs(norm(p) - 1.0), true};
    case ShapeKind::kTorus: {
      const double rho = std::hypot(p.x, p.y);
      const Vec3f ring{float(p.x / rho), float(p.y / rho), 0};
      const Vec3f d = p - ring;
      return {d / norm(d), std::abs(norm(d) - 0.35), true};
    }
    case ShapeKind::kTwoSpheres: {
      const Vec3f c{patch == 0 ? -0.6f : 0.6f, 0, 0}, other{-c.x, 0, 0};
      const Vec3f d = p - c;
      const bool outside_other = norm(p - other) >= 1 - 1e-6;
      return {d / norm(d), std::abs(norm(d) - 1.0), o.keep_inside || outside_other};
    }
    case ShapeKind::kCube: {
      const int axis = static_cast<int>(patch / 2);
      Vec3f n{0, 0, 0};
      n[axis] = patch % 2 ? 1.0f : -1.0f;
      const bool inside =
          std::abs(p.x) <= 1 + 1e-6 && std::abs(p.y) <= 1 + 1e-6 && std::abs(p.z) <= 1 + 1e-6;
      return {n, std::abs(p[axis] - n[axis]), inside};
    }
    case ShapeKind::kCadPart:
      return expect_cad(patch, p);
  }
  return {{0, 0, 0}, 1e9, false};
}

std::vector<ShapeOptions> all_variants(std::size_t points) {
  std::vector<ShapeOptions> v;
  for (ShapeKind k : kAllKinds)
    for (bool random : {false, true}) v.push_back(shape(k, points, random));
  v.push_back(shape(ShapeKind::kTwoSpheres, points));
  v.back().keep_inside = true;
  return v;
}

std::string label(const ShapeOptions& o) {
  return shape_kind_name(o.kind) + (o.random ? " random" : " stratified") +
         (o.keep_inside ? " keep-inside" : "");
}

TEST(SyntheticShapes, SphereNormalsAreUnitAndExactlyRadial) {
  const SplatCloud c = make_shape(shape(ShapeKind::kSphere, 5000));
  ASSERT_GT(c.size(), 4900u);
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_NEAR(norm(c.normals[i]), 1.0f, 1e-6f);
    // A unit sphere at the origin: the exact normal is the position itself, to the bit.
    ASSERT_EQ(c.normals[i], c.positions[i]) << "point " << i;
  }
}

TEST(SyntheticShapes, PointsLieOnTheirLabelledPatchWithItsOutwardNormal) {
  for (const ShapeOptions& o : all_variants(3000)) {
    const SplatCloud c = make_shape(o);
    const auto& ids = patch_ids(c);
    const std::size_t patches = shape_patch_names(o).size();
    std::vector<int> per_patch(patches, 0);
    ASSERT_EQ(ids.size(), c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      const auto patch = static_cast<uint32_t>(ids[i]);
      ASSERT_LT(patch, patches) << label(o);
      ++per_patch[patch];
      const Expected e = expect(o, patch, c.positions[i]);
      ASSERT_LT(e.off_surface, 1e-5) << label(o) << " point " << i << " patch " << patch;
      ASSERT_TRUE(e.in_region) << label(o) << " point " << i << " patch " << patch;
      ASSERT_LT(norm(c.normals[i] - e.normal), 1e-5f) << label(o) << " point " << i;
      ASSERT_NEAR(norm(c.normals[i]), 1.0f, 1e-6f);
      ASSERT_LT(distance_to_patch(o, patch, c.positions[i]), 1e-5f) << label(o);
      ASSERT_LT(distance_to_shape(o, c.positions[i]), 1e-5f) << label(o);
    }
    for (std::size_t k = 0; k < patches; ++k) EXPECT_GT(per_patch[k], 10) << label(o) << " " << k;
  }
}

TEST(SyntheticShapes, DistanceToPatchIsZeroOnlyOnThatPatch) {
  const ShapeOptions o = shape(ShapeKind::kCadPart, 100);
  EXPECT_NEAR(distance_to_patch(o, 1, {-0.1f, 0.5f, 1.5f}), 0.3f, 1e-6f);  // above the top
  EXPECT_NEAR(distance_to_patch(o, 1, {0.2f, 0, 1.2f}), 0.25f, 1e-6f);     // in the hole's mouth
  EXPECT_NEAR(distance_to_patch(o, 8, {0.2f, 0, 0.6f}), 0.25f, 1e-6f);     // on the hole's axis
  EXPECT_NEAR(distance_to_patch(o, 6, {-0.7f, 0, 2.7f}), std::hypot(0.4f, 1.0f), 1e-6f);
  EXPECT_NEAR(distance_to_shape(o, {-0.7f, 0, 2.7f}), 1.0f, 1e-6f);  // above the boss top
  EXPECT_THROW(distance_to_patch(o, 9, {0, 0, 0}), std::out_of_range);
  const ShapeOptions t = shape(ShapeKind::kTorus, 100);
  EXPECT_NEAR(distance_to_shape(t, {0, 0, 0}), 0.65f, 1e-6f);
  EXPECT_NEAR(distance_to_shape(t, {1, 0, 0}), 0.35f, 1e-6f);
  ShapeOptions two = shape(ShapeKind::kTwoSpheres, 100);
  // The union lacks the cap of the red sphere inside the blue one; keep_inside has it.
  EXPECT_GT(distance_to_patch(two, 0, {0.4f, 0, 0}), 0.1f);
  two.keep_inside = true;
  EXPECT_NEAR(distance_to_patch(two, 0, {0.4f, 0, 0}), 0.0f, 1e-6f);
}

TEST(SyntheticShapes, CountsAreCloseToTheRequest) {
  for (const ShapeOptions& o : all_variants(20000)) {
    const SplatCloud c = make_shape(o);
    if (o.random) {
      EXPECT_EQ(c.size(), 20000u) << label(o);
    } else {
      EXPECT_NEAR(static_cast<double>(c.size()), 20000.0, 200.0) << label(o);
    }
  }
  EXPECT_GE(make_shape(shape(ShapeKind::kSphere, 1)).size(), 1u);
}

TEST(SyntheticShapes, PatchAreasMatchTheSampleShares) {
  // Area-uniform sampling: each patch's share of the points is its share of the area.
  for (bool random : {false, true}) {
    const ShapeOptions o = shape(ShapeKind::kCadPart, 40000, random);
    const SplatCloud c = make_shape(o);
    const double h2 = cad_area() / static_cast<double>(c.size());
    std::vector<double> count(9, 0);
    for (double id : patch_ids(c)) count[static_cast<std::size_t>(id)] += 1;
    // Stratified counts are within rounding of the share; random ones within 4 binomial sigmas.
    auto tolerance = [&](double area) {
      return random ? 4 * std::sqrt(area / h2) * h2 : 0.02 * area;
    };
    const double hole_side = 2 * kPi * 0.25 * 1.2, boss_top = kPi * 0.16, left = 2.4;
    EXPECT_NEAR(count[8] * h2, hole_side, tolerance(hole_side));
    EXPECT_NEAR(count[7] * h2, boss_top, tolerance(boss_top));
    EXPECT_NEAR(count[2] * h2, left, tolerance(left));
  }
}

TEST(SyntheticShapes, SurfacesAreClosedAndNormalsPointOutward) {
  // Divergence theorem on the sample: Σ n dA = 0 and Σ (p·n) dA / 3 = volume. A flipped patch
  // normal or a missing patch breaks both.
  const double top_end = 1.5 - 1.2 / std::sqrt(3.0);
  const double cad_volume =
      (3 + top_end + 1.5) / 2 * 1.2 * 2 + kPi * 0.16 * 0.5 - kPi * 0.0625 * 1.2;
  struct Case {
    ShapeKind kind;
    double area, volume;
  } cases[] = {{ShapeKind::kSphere, 4 * kPi, 4 * kPi / 3},
               {ShapeKind::kTorus, 4 * kPi * kPi * 0.35, 2 * kPi * kPi * 0.35 * 0.35},
               {ShapeKind::kCube, 24, 8},
               {ShapeKind::kCadPart, cad_area(), cad_volume}};
  for (const Case& k : cases) {
    const SplatCloud c = make_shape(shape(k.kind, 40000));
    const double da = k.area / static_cast<double>(c.size());
    double flux[3] = {0, 0, 0}, volume = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      for (int a = 0; a < 3; ++a) flux[a] += c.normals[i][a] * da;
      volume += dot(c.positions[i], c.normals[i]) * da / 3;
    }
    EXPECT_LT(std::hypot(flux[0], flux[1], flux[2]), 0.01 * k.area) << shape_kind_name(k.kind);
    EXPECT_NEAR(volume, k.volume, 0.01 * k.volume) << shape_kind_name(k.kind);
  }
}

TEST(SyntheticShapes, CadCreasesAreBetween60And120Degrees) {
  const ShapeOptions o = shape(ShapeKind::kCadPart, 2000);
  const SplatCloud c = make_shape(o);
  const auto& ids = patch_ids(c);
  std::vector<Vec3f> normal(9);
  for (std::size_t i = 0; i < c.size(); ++i)
    normal[static_cast<std::size_t>(ids[i])] = c.normals[i];
  auto dihedral = [&](int a, int b) {
    return 180.0 - std::acos(std::clamp(dot(normal[a], normal[b]), -1.0f, 1.0f)) * 180 / kPi;
  };
  EXPECT_NEAR(dihedral(0, 3), 60.0, 1e-4);   // bottom / bevel
  EXPECT_NEAR(dihedral(1, 3), 120.0, 1e-4);  // top / bevel
  EXPECT_NEAR(dihedral(0, 2), 90.0, 1e-4);   // bottom / left
  EXPECT_NEAR(dihedral(3, 4), 90.0, 1e-4);   // bevel / front
  EXPECT_NEAR(dihedral(1, 7), 180.0, 1e-4);  // top and boss top are parallel (not adjacent)
  EXPECT_EQ(shape_patch_names(o),
            (std::vector<std::string>{"bottom", "top", "left", "bevel", "front", "back",
                                      "boss-side", "boss-top", "hole"}));
}

TEST(SyntheticShapes, SameSeedSameBytesOtherSeedOtherBytes) {
  for (bool random : {false, true}) {
    ShapeOptions o = shape(ShapeKind::kCadPart, 5000, random);
    o.noise = 0.002;
    const SplatCloud a = make_shape(o), b = make_shape(o);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(Vec3f)));
    EXPECT_EQ(0, std::memcmp(a.normals.data(), b.normals.data(), a.size() * sizeof(Vec3f)));
    EXPECT_EQ(a.radii, b.radii);
    EXPECT_EQ(patch_ids(a), patch_ids(b));
    o.seed = 2;
    const SplatCloud c = make_shape(o);
    EXPECT_TRUE(c.size() != a.size() ||
                std::memcmp(a.positions.data(), c.positions.data(), a.size() * sizeof(Vec3f)));
  }
}

TEST(SyntheticShapes, SameSeedSameFileBytes) {
  std::string pattern = testing::TempDir() + "synthetic_shapes_XXXXXX";
  ASSERT_NE(mkdtemp(pattern.data()), nullptr);  // unique even across concurrent test runs
  const std::string dir = pattern;
  auto write = [&](uint64_t seed, const std::string& name) {
    ShapeOptions o = shape(ShapeKind::kTwoSpheres, 3000);
    o.seed = seed;
    LoadedCloud doc;
    doc.cloud = make_shape(o);
    write_cloud(doc, dir + "/" + name);
    std::ifstream in(dir + "/" + name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string a = write(7, "a.ply"), b = write(7, "b.ply"), c = write(8, "c.ply");
  EXPECT_GT(a.size(), 3000u * 30);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::filesystem::remove_all(dir);
}

TEST(SyntheticShapes, RngIsPinned) {
  // The generator's numbers are part of the data-samples' reproducibility: pin them.
  DeterministicRng rng(1);
  const uint64_t first = rng.next(), second = rng.next();
  DeterministicRng again(1), other(1, 1);
  EXPECT_EQ(again.next(), first);
  EXPECT_EQ(again.next(), second);
  EXPECT_NE(other.next(), first);
  EXPECT_EQ(first, 0xee127fe613436e33ull);
  EXPECT_EQ(second, 0xd6dad8d34a1874eaull);
  double sum = 0, sum2 = 0;
  DeterministicRng g(3);
  for (int i = 0; i < 100000; ++i) {
    const double x = g.normal();
    sum += x;
    sum2 += x * x;
  }
  EXPECT_NEAR(sum / 1e5, 0.0, 0.02);
  EXPECT_NEAR(sum2 / 1e5, 1.0, 0.02);
}

TEST(SyntheticShapes, NoiseIsGaussianAlongTheExactNormal) {
  ShapeOptions o = shape(ShapeKind::kSphere, 100000);
  const SplatCloud clean = make_shape(o);
  o.noise = 0.01;
  const SplatCloud noisy = make_shape(o);
  ASSERT_EQ(clean.size(), noisy.size());
  const double sigma = 0.01 * 2 * std::sqrt(3.0);  // bbox [-1, 1]^3
  EXPECT_NEAR(shape_bounds(o).diagonal(), 2 * std::sqrt(3.0), 1e-6);
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    ASSERT_EQ(noisy.normals[i], clean.normals[i]);
    const Vec3f d = noisy.positions[i] - clean.positions[i];
    ASSERT_LT(norm(cross(d, noisy.normals[i])), 1e-6f);  // moved along the normal only
    const double offset = dot(d, noisy.normals[i]);
    sum += offset;
    sum2 += offset * offset;
  }
  const double n = static_cast<double>(noisy.size());
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sd, sigma, 0.05 * sigma);
  EXPECT_NEAR(mean, 0.0, 5 * sigma / std::sqrt(n));
}

// Mean distance to the 5 nearest neighbours of every point, by brute force.
double mean_5nn(const SplatCloud& c) {
  double total = 0;
  std::vector<float> d(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (std::size_t j = 0; j < c.size(); ++j)
      d[j] = j == i ? std::numeric_limits<float>::infinity()
                    : std::sqrt(squared_distance(c.positions[i], c.positions[j]));
    std::partial_sort(d.begin(), d.begin() + 5, d.end());
    total += (d[0] + d[1] + d[2] + d[3] + d[4]) / 5.0;
  }
  return total / static_cast<double>(c.size());
}

TEST(SyntheticShapes, RadiiMatchTheMeanDistanceToFiveNeighbours) {
  // Stratified: the radius is the measured 5-NN mean, 1.05 h (never less), where h² is the area
  // per point. Random: the Poisson expectation 0.902 h of the 5-NN mean is what the sample shows.
  const std::size_t n = 4000;
  const double h = std::sqrt(4 * kPi / n);
  const SplatCloud s = make_shape(shape(ShapeKind::kSphere, n));
  const double measured = mean_5nn(s);
  EXPECT_NEAR(measured / h, 1.05, 0.03);
  for (float r : s.radii) ASSERT_GE(r, 1.05 * h * (1 - 1e-6));
  double mean_radius = 0;
  for (float r : s.radii) mean_radius += r / static_cast<double>(s.size());
  EXPECT_NEAR(mean_radius / measured, 1.0, 0.06);

  const SplatCloud r = make_shape(shape(ShapeKind::kSphere, n, true));
  EXPECT_NEAR(mean_5nn(r) / h, 0.902, 0.03);
  EXPECT_NEAR(r.radii[0] / h, std::sqrt(std::log(1e4) / kPi), 1e-4);
}

// Fraction of the query points q (on the surface) not covered by any splat: a splat covers q when
// q's projection on the splat plane is within the radius of its centre.
double uncovered_fraction(const SplatCloud& splats, const SplatCloud& queries,
                          const std::vector<bool>& use) {
  std::size_t missed = 0, used = 0;
  for (std::size_t k = 0; k < queries.size(); ++k) {
    if (!use[k]) continue;
    ++used;
    const Vec3f& q = queries.positions[k];
    bool covered = false;
    for (std::size_t i = 0; i < splats.size() && !covered; ++i) {
      const Vec3f d = q - splats.positions[i];
      const float along = dot(d, splats.normals[i]);
      covered = squared_norm(d) - along * along <= splats.radii[i] * splats.radii[i] &&
                std::abs(along) < splats.radii[i];
    }
    missed += !covered;
  }
  return static_cast<double>(missed) / static_cast<double>(std::max<std::size_t>(used, 1));
}

TEST(SyntheticShapes, StratifiedSplatsCoverTheSurfaceWithoutHoles) {
  for (ShapeKind kind : {ShapeKind::kSphere, ShapeKind::kTorus}) {
    const SplatCloud splats = make_shape(shape(kind, 2000));
    ShapeOptions qo = shape(kind, 20000, true);
    qo.seed = 99;
    const SplatCloud queries = make_shape(qo);
    EXPECT_EQ(uncovered_fraction(splats, queries, std::vector<bool>(queries.size(), true)), 0.0)
        << shape_kind_name(kind);
  }
  // Faces with creases: each patch covers itself away from the slanted edges' slivers (within
  // h/2 of a crease a neighbouring patch's splats overlap instead).
  for (ShapeKind kind : {ShapeKind::kCube, ShapeKind::kCadPart}) {
    const SplatCloud splats = make_shape(shape(kind, 3000));
    ShapeOptions qo = shape(kind, 20000, true);
    qo.seed = 99;
    const SplatCloud queries = make_shape(qo);
    const float h = std::sqrt(static_cast<float>(total_area(qo) / 3000));
    std::vector<bool> use(queries.size());
    for (std::size_t k = 0; k < queries.size(); ++k)
      use[k] = distance_to_crease(kind, queries.positions[k]) > h / 2;
    EXPECT_EQ(uncovered_fraction(splats, queries, use), 0.0) << shape_kind_name(kind);
  }
}

TEST(SyntheticShapes, RandomSplatsLeaveAtMostATinyFractionUncovered) {
  const SplatCloud splats = make_shape(shape(ShapeKind::kSphere, 2000, true));
  ShapeOptions qo = shape(ShapeKind::kSphere, 20000, true);
  qo.seed = 99;
  const SplatCloud queries = make_shape(qo);
  EXPECT_LT(uncovered_fraction(splats, queries, std::vector<bool>(queries.size(), true)), 1e-3);
}

TEST(SyntheticShapes, DistanceToCreaseMatchesHandWorkedPoints) {
  EXPECT_FLOAT_EQ(distance_to_crease(ShapeKind::kCube, {1, 1, 0}), 0.0f);
  EXPECT_FLOAT_EQ(distance_to_crease(ShapeKind::kCube, {0, 0, 1}), 1.0f);
  EXPECT_FLOAT_EQ(distance_to_crease(ShapeKind::kCube, {0.5f, 1, 0.2f}), 0.5f);
  EXPECT_NEAR(distance_to_crease(ShapeKind::kCube, {2, 2, 0}), std::sqrt(2.0f), 1e-6f);
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(distance_to_crease(ShapeKind::kSphere, {1, 0, 0}), inf);
  EXPECT_EQ(distance_to_crease(ShapeKind::kTorus, {1, 0, 0}), inf);
  EXPECT_NEAR(distance_to_crease(ShapeKind::kTwoSpheres, {0, 0, 0}), 0.8f, 1e-6f);
  EXPECT_NEAR(distance_to_crease(ShapeKind::kTwoSpheres, {0, 0, 0.8f}), 0.0f, 1e-6f);
  // CAD part: the 60° edge, the hole's bottom rim, the middle of the bevel, the boss top centre.
  EXPECT_NEAR(distance_to_crease(ShapeKind::kCadPart, {1.5f, 0.3f, 0}), 0.0f, 1e-6f);
  EXPECT_NEAR(distance_to_crease(ShapeKind::kCadPart, {0, 0, 0}), 0.05f, 1e-6f);
  const float x = 1.5f - 0.6f * std::tan(static_cast<float>(kPi / 6));
  EXPECT_NEAR(distance_to_crease(ShapeKind::kCadPart, {x, 0, 0.6f}), 0.6f / std::sin(kPi / 3),
              1e-5f);
  EXPECT_NEAR(distance_to_crease(ShapeKind::kCadPart, {-0.7f, 0, 1.7f}), 0.4f, 1e-6f);
}

TEST(SyntheticShapes, DistanceToCreaseMatchesBruteForceOverTheCreasePoints) {
  // The CAD part's creases written out again and sampled densely: 12 prism edges, 4 circles.
  const double top_end = 1.5 - 1.2 / std::sqrt(3.0);
  const double profile[4][2] = {{-1.5, 0}, {1.5, 0}, {top_end, 1.2}, {-1.5, 1.2}};
  std::vector<Vec3f> crease;
  auto line = [&](Vec3f a, Vec3f b) {
    for (int i = 0; i <= 4000; ++i) crease.push_back(a + (b - a) * (i / 4000.0f));
  };
  for (int i = 0; i < 4; ++i) {
    const auto* p = profile[i];
    const auto* q = profile[(i + 1) % 4];
    const Vec3f pf{float(p[0]), -1, float(p[1])}, pb{float(p[0]), 1, float(p[1])};
    line(pf, pb);
    line(pf, {float(q[0]), -1, float(q[1])});
    line(pb, {float(q[0]), 1, float(q[1])});
  }
  const double circles[4][4] = {
      {-0.7, 1.2, 0.4}, {-0.7, 1.7, 0.4}, {0.2, 1.2, 0.25}, {0.2, 0, 0.25}};
  for (const auto& c : circles)
    for (int i = 0; i < 4000; ++i) {
      const double a = 2 * kPi * i / 4000;
      crease.push_back({float(c[0] + c[2] * std::cos(a)), float(c[2] * std::sin(a)), float(c[1])});
    }
  DeterministicRng rng(5);
  for (int k = 0; k < 300; ++k) {
    const Vec3f p{float(rng.uniform(-2, 2)), float(rng.uniform(-1.5, 1.5)),
                  float(rng.uniform(-0.5, 2.2))};
    float best = std::numeric_limits<float>::infinity();
    for (const Vec3f& c : crease) best = std::min(best, norm(p - c));
    // The dense sampling overestimates by at most half its step (0.0015).
    EXPECT_NEAR(distance_to_crease(ShapeKind::kCadPart, p), best, 0.002f) << k;
    EXPECT_LE(distance_to_crease(ShapeKind::kCadPart, p), best + 1e-5f) << k;
  }
}

TEST(SyntheticShapes, TwoSpheresColoursAndInsideParts) {
  for (bool keep : {false, true}) {
    ShapeOptions o = shape(ShapeKind::kTwoSpheres, 8000);
    o.keep_inside = keep;
    const SplatCloud c = make_shape(o);
    const auto& ids = patch_ids(c);
    std::size_t inside = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const bool red = ids[i] == 0;
      ASSERT_EQ(c.colors[i],
                (red ? std::array<uint16_t, 3>{255, 0, 0} : std::array<uint16_t, 3>{0, 0, 255}));
      const Vec3f other{red ? 0.6f : -0.6f, 0, 0};
      inside += norm(c.positions[i] - other) < 1 - 1e-4f;
    }
    // The part of each sphere inside the other is a cap of area 2π·0.4 of the 4π.
    if (keep)
      EXPECT_NEAR(static_cast<double>(inside) / c.size(), 0.2, 0.01);
    else
      EXPECT_EQ(inside, 0u);
  }
  const SplatCloud grey = make_shape(shape(ShapeKind::kTorus, 100));
  EXPECT_EQ(grey.colors[0], (std::array<uint16_t, 3>{200, 200, 200}));
  EXPECT_EQ(grey.color_bits, 8);
}

TEST(SyntheticShapes, BoundsContainTheSampleAndAreTight) {
  for (ShapeKind kind : kAllKinds) {
    const ShapeOptions o = shape(kind, 20000);
    const Bounds b = shape_bounds(o), s = compute_bounds(make_shape(o));
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(s.min[a], b.min[a] - 1e-6f) << shape_kind_name(kind);
      EXPECT_LE(s.max[a], b.max[a] + 1e-6f) << shape_kind_name(kind);
      EXPECT_NEAR(s.min[a], b.min[a], 0.05f) << shape_kind_name(kind);
      EXPECT_NEAR(s.max[a], b.max[a], 0.05f) << shape_kind_name(kind);
    }
  }
}

// --texture: the same points; colours that vary smoothly over the surface with a little noise,
// and an intensity attribute; the same bytes for the same seed.
TEST(SyntheticShapes, TextureKeepsThePointsAndVariesColoursAndIntensity) {
  ShapeOptions o = shape(ShapeKind::kCadPart, 20000);
  o.scan_lines = 4;
  const SplatCloud plain = make_shape(o);
  o.texture = true;
  const SplatCloud a = make_shape(o), b = make_shape(o);
  EXPECT_EQ(a.positions, plain.positions);
  EXPECT_EQ(a.normals, plain.normals);
  EXPECT_EQ(a.radii, plain.radii);
  EXPECT_EQ(a.colors, b.colors);
  const ExtraAttribute* intensity = a.find_extra("intensity");
  ASSERT_NE(intensity, nullptr);
  EXPECT_EQ(intensity->type(), ScalarType::kUInt16);
  EXPECT_EQ(intensity->values, b.find_extra("intensity")->values);
  EXPECT_EQ(plain.find_extra("intensity"), nullptr);
  // Channels span much of their range; a point and its nearest neighbour differ by little, two
  // points far apart by much more: a texture, not noise.
  int lo = 255, hi = 0;
  for (const auto& c : a.colors) {
    lo = std::min<int>(lo, c[0]);
    hi = std::max<int>(hi, c[0]);
  }
  EXPECT_GT(hi - lo, 100);
  double near_step = 0, far_step = 0;
  const std::size_t probes = 200;
  for (std::size_t p = 0; p < probes; ++p) {
    const std::size_t i = p * (a.size() / probes);
    std::size_t nearest = i == 0 ? 1 : 0;
    for (std::size_t j = 0; j < a.size(); ++j)
      if (j != i && squared_norm(a.positions[j] - a.positions[i]) <
                        squared_norm(a.positions[nearest] - a.positions[i]))
        nearest = j;
    near_step += std::abs(a.colors[i][0] - a.colors[nearest][0]);
    far_step += std::abs(a.colors[i][0] - a.colors[(i + a.size() / 2) % a.size()][0]);
  }
  EXPECT_LT(near_step, far_step / 3) << near_step / probes << " " << far_step / probes;
  double ilo = 1e9, ihi = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ilo = std::min(ilo, intensity->values[i]);
    ihi = std::max(ihi, intensity->values[i]);
  }
  EXPECT_GT(ihi - ilo, 500);
}

TEST(SyntheticShapes, NamesParseAndBadOptionsAreUsageErrors) {
  for (ShapeKind kind : kAllKinds) EXPECT_EQ(parse_shape_kind(shape_kind_name(kind)), kind);
  auto kind_of = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.kind();
    }
    return ErrorKind::kOutput;  // "did not throw"
  };
  EXPECT_EQ(kind_of([] { parse_shape_kind("blob"); }), ErrorKind::kUsage);
  EXPECT_EQ(kind_of([] { make_shape(shape(ShapeKind::kCube, 0)); }), ErrorKind::kUsage);
  ShapeOptions o = shape(ShapeKind::kCube, 10);
  o.noise = -0.1;
  EXPECT_EQ(kind_of([&] { make_shape(o); }), ErrorKind::kUsage);
  o.noise = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(kind_of([&] { make_shape(o); }), ErrorKind::kUsage);
  const SplatCloud c = make_shape(shape(ShapeKind::kCube, 10));
  const ExtraAttribute* ids = c.find_extra("patch_id");
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ(ids->type(), ScalarType::kUInt32);
}

}  // namespace
}  // namespace splatkit
