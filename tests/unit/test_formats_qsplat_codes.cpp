// The four .qs v11 quantisers (formats/qsplat_codes.h): the sphere table as the original builds
// it, and every quantiser's round trip within its stated error; the sphere encoder's
// conservative guarantee on random children.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "formats/qsplat_codes.h"

namespace splatkit::qsplat {
namespace {

TEST(QSplatCodes, SphereTableHas7621CellsInTheOriginalOrder) {
  const auto& t = sphere_cells();
  ASSERT_EQ(t.size(), 7621u);
  // size 1, x = 0, y = 0: the first z whose cell is inside |XYZ| <= 1 + sqrt(3)/13 is z = 4 ...
  // rather than pin that by hand, pin the first and last cells and the count per size.
  EXPECT_FLOAT_EQ(t[0].r, 1.0f / 13);
  EXPECT_EQ(t[7620].x, 0.0f);
  EXPECT_EQ(t[7620].y, 0.0f);
  EXPECT_EQ(t[7620].z, 0.0f);
  EXPECT_EQ(t[7620].r, 1.0f);  // the parent itself, exactly
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_LE(t[i - 1].r, t[i].r);
  for (const SphereCell& c : t) {
    const float lim = 1 + std::sqrt(3.0f) * c.r;
    EXPECT_LE(c.x * c.x + c.y * c.y + c.z * c.z, lim * lim);
  }
}

TEST(QSplatCodes, SphereEncoderIsConservative) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), f(0, 1);
  const Sphere parent{{3.5f, -2.0f, 10.0f}, 2.0f};
  int worst_size = 0;
  for (int i = 0; i < 20000; ++i) {
    double d[3] = {u(rng), u(rng), u(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 1) continue;
    const double rho = (1 - len) * std::pow(f(rng), 3);  // the child lies inside the parent
    const double c[3] = {parent.centre.x + parent.radius * d[0],
                         parent.centre.y + parent.radius * d[1],
                         parent.centre.z + parent.radius * d[2]};
    const int s = encode_sphere(parent, c, rho * parent.radius);
    ASSERT_GE(s, 0);
    const Sphere q = decode_sphere(sphere_cells()[s], parent);
    const double dx = q.centre.x - c[0], dy = q.centre.y - c[1], dz = q.centre.z - c[2];
    EXPECT_LE(std::sqrt(dx * dx + dy * dy + dz * dz) + rho * parent.radius, double{q.radius});
    const double px = q.centre.x - parent.centre.x, py = q.centre.y - parent.centre.y,
                 pz = q.centre.z - parent.centre.z;
    EXPECT_LE(std::sqrt(px * px + py * py + pz * pz) + q.radius, double{parent.radius});
    worst_size = std::max(worst_size, static_cast<int>(std::lround(sphere_cells()[s].r * 13)));
  }
  EXPECT_EQ(worst_size, 13);  // a child touching the parent's surface needs the whole parent
}

TEST(QSplatCodes, SphereEncoderPicksTheSmallestCellThatFits) {
  const Sphere parent{{0, 0, 0}, 1};
  const double c[3] = {0, 0, 0};
  EXPECT_EQ(encode_sphere(parent, c, 1.0), 7620);
  const int s = encode_sphere(parent, c, 0.3);
  EXPECT_NEAR(sphere_cells()[s].r, 5.0f / 13, 1e-6);  // 4/13 cannot hold a centred 0.3 sphere
}

// The nearest-first search must return the exhaustive search's code, cell for cell: children
// anywhere in parents near the origin and far from it (where float rounding of the decoded
// centres is coarse against the grid), and children centred on the grid's cells and halfway
// between them, where two cells are equally near and the first in the table's order wins.
TEST(QSplatCodes, NearestFirstSearchFindsTheExhaustiveSearchsCell) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), f(0, 1);
  const Sphere parents[] = {{{0, 0, 0}, 1},
                            {{3.5f, -2.0f, 10.0f}, 2.0f},
                            {{1e5f, 2e5f, -3e4f}, 0.01f},
                            {{-7e3f, 5e2f, 1e3f}, 0.3f},
                            {{1e6f, 1e6f, 1e6f}, 2e-3f}};
  int cases = 0, not_found = 0;
  for (const Sphere& parent : parents)
    for (int i = 0; i < 40000; ++i) {
      double d[3] = {u(rng), u(rng), u(rng)};
      if (i % 4 == 1 || i % 4 == 2) {
        // Snap to the grid of cell centres of a random size (steps of 1/13 parent radii: on a
        // cell centre or halfway between two).
        for (double& c : d) c = std::round(c * 13) / 13;
      }
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (len >= 1) continue;
      // Radii as a tree makes them (a third to four fifths of the parent) and any other.
      const double rho = i % 2 ? (1 - len) * (0.3 + 0.5 * f(rng)) : (1 - len) * std::pow(f(rng), 3);
      const double c[3] = {parent.centre.x + parent.radius * d[0],
                           parent.centre.y + parent.radius * d[1],
                           parent.centre.z + parent.radius * d[2]};
      const double r = rho * parent.radius;
      const int fast = encode_sphere(parent, c, r);
      const int full = encode_sphere(parent, c, r, SphereSearch::kExhaustive);
      ASSERT_EQ(fast, full) << "parent " << parent.centre.x << " radius " << parent.radius
                            << ", child at " << d[0] << " " << d[1] << " " << d[2] << " radius "
                            << rho;
      ++cases;
      not_found += fast < 0;
    }
  EXPECT_GT(cases, 100000);
  EXPECT_EQ(not_found, 0);  // every child inside its parent finds a cell
}

// The leaf rule (SphereEncoder::nearest_disc), against every cell of the table: of the two sizes
// around 13 r / R, the cell nearest the leaf's centre on every axis, the one of least
// grown + kBareWeight · bare that lies inside the parent; when neither does, the answer must still
// lie inside the parent. A leaf equal to a cell's decoded sphere takes that cell (both bands 0).
double disc_cost(const Sphere& q, const double c[3], double radius, const Vec3f& n) {
  const double dx = double{q.centre.x} - c[0], dy = double{q.centre.y} - c[1],
               dz = double{q.centre.z} - c[2];
  const double across = std::fabs(dx * n.x + dy * n.y + dz * n.z);
  const double along = std::sqrt(std::max(0.0, dx * dx + dy * dy + dz * dz - across * across));
  return std::max(0.0, q.radius + along - radius) +
         kBareWeight * std::max(0.0, radius + along + kDiscSlope * across - q.radius);
}

bool inside(const Sphere& q, const Sphere& parent) {
  const double px = double{q.centre.x} - parent.centre.x, py = double{q.centre.y} - parent.centre.y,
               pz = double{q.centre.z} - parent.centre.z;
  return std::sqrt(px * px + py * py + pz * pz) + q.radius <= parent.radius;
}

TEST(QSplatCodes, NearestDiscTakesTheBestOfTheNearestCellsOfTwoSizes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1), f(0, 1);
  const Sphere parent{{-1.5f, 0.25f, 4.0f}, 0.75f};
  const SphereEncoder encode(parent);
  int compared = 0, edge = 0;
  for (int i = 0; i < 3000; ++i) {
    double d[3] = {u(rng), u(rng), u(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 1) continue;
    const double radius = (1 - len) * (0.05 + 0.6 * f(rng)) * parent.radius;
    const double c[3] = {parent.centre.x + parent.radius * d[0],
                         parent.centre.y + parent.radius * d[1],
                         parent.centre.z + parent.radius * d[2]};
    const Vec3f n = normalized(Vec3f{float(u(rng)), float(u(rng)), float(u(rng))});
    const int below = std::clamp(static_cast<int>(std::floor(radius / parent.radius * 13)), 1, 12);
    int want = -1;
    double want_cost = 0;
    for (int s = 0; s < kSphereCells; ++s) {
      const SphereCell& cell = sphere_cells()[s];
      const int size = static_cast<int>(std::lround(cell.r * 13));
      if (size != below && size != below + 1) continue;
      // Nearest on every axis: the cell centre within half a grid step (1/13) of the leaf's, or
      // the first or last index when the leaf lies beyond them.
      bool nearest = true;
      for (int k = 0; k < 3; ++k) {
        const double x = (k == 0 ? cell.x : k == 1 ? cell.y : cell.z);
        const double at = d[k], lo = size / 13.0 - 1, hi = 1 - size / 13.0;
        const double clamped = std::clamp(at, lo, hi);
        if (std::fabs(x - clamped) > 1.0 / 13 + 1e-6) nearest = false;
      }
      const Sphere q = decode_sphere(cell, parent);
      if (!nearest || !inside(q, parent)) continue;
      const double cost = disc_cost(q, c, radius, n);
      if (want < 0 || cost < want_cost) {
        want = s;
        want_cost = cost;
      }
    }
    Sphere decoded;
    const int got = encode.nearest_disc(c, radius, n, &decoded);
    ASSERT_GE(got, 0) << i;
    const Sphere q = decode_sphere(sphere_cells()[got], parent);
    EXPECT_EQ(std::memcmp(&q, &decoded, sizeof q), 0) << i;
    EXPECT_TRUE(inside(q, parent)) << i;
    if (want < 0) {
      ++edge;
      continue;
    }
    ++compared;
    EXPECT_NEAR(disc_cost(q, c, radius, n), want_cost, 1e-9 * parent.radius) << i;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(edge, 0);  // leaves on the parent's edge take the wider searches
  // A leaf that is a cell's decoded sphere takes that cell.
  for (int s = 0; s < kSphereCells; s += 7) {
    const Sphere q = decode_sphere(sphere_cells()[s], parent);
    if (!inside(q, parent)) continue;
    const double c[3] = {q.centre.x, q.centre.y, q.centre.z};
    EXPECT_EQ(encode.nearest_disc(c, q.radius, Vec3f{0, 0, 1}), s) << s;
  }
}

TEST(QSplatCodes, NormalsRoundTripWithinTheStatedError) {
  double worst = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double z = -1 + (i + 0.5) * 2.0 / n, phi = (j + 0.5) * M_PI / n;
      const double s = std::sqrt(1 - z * z);
      const Vec3f v{static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)),
                    static_cast<float>(z)};
      const int q = encode_normal(v);
      ASSERT_GE(q, 0);
      ASSERT_LT(q, kNormalCodes);
      const Vec3f& d = decode_normal(q);
      EXPECT_NEAR(norm(d), 1.0f, 1e-5f);
      worst = std::max(worst, std::acos(std::min(1.0, static_cast<double>(dot(d, v)))));
    }
  EXPECT_LE(worst, kNormalMaxError);
  RecordProperty("worst_normal_error_rad", std::to_string(worst));
  // Axis-aligned normals stay on their axis's face.
  EXPECT_EQ(encode_normal({0, 0, 1}) / (52 * 52), 4);
  EXPECT_EQ(encode_normal({0, 0, -1}) / (52 * 52), 5);
  EXPECT_EQ(encode_normal({-1, 0, 0}) / (52 * 52), 1);
}

// The normal encoder's choice, checked against its definition: the original's cell (each stored
// component's step: the count of k in 1..51 with c >= tan((k/26 − 1)·π/4)) or a code of its 3 × 3
// neighbourhood on the same face that is strictly closer (dot product), never one that a closer
// neighbour beats. Random directions, and directions at the faces' rims, where the
// neighbourhood leaves the face or holds codes outside the unit circle (decoded with a zero
// dominant component; the encoder never picks them).
TEST(QSplatCodes, NormalEncoderPicksTheClosestCodeAroundTheOriginalsCell) {
  auto step = [](float c) {
    int k = 0;
    for (int b = 1; b < kNormalSteps; ++b)
      k += c >= static_cast<float>(std::tan((2.0 * b / kNormalSteps - 1.0) * M_PI / 4));
    return k;
  };
  std::mt19937 rng(5);
  std::normal_distribution<float> g;
  std::uniform_real_distribution<float> rim(0.95f, 1.0f);
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    Vec3f n{g(rng), g(rng), g(rng)};
    if (i % 2) {  // near a face's rim: the dominant component barely above another one
      n.x = std::copysign(std::max(std::fabs(n.y), std::fabs(n.z)) / rim(rng), n.x);
    }
    if (!(squared_norm(n) > 0)) continue;
    const Vec3f m = normalized(n);
    const float a[3] = {std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)};
    const int axis = (a[0] > a[1] ? a[0] : a[1]) > a[2] ? (a[0] > a[1] ? 0 : 1) : 2;
    const float mc[3] = {m.x, m.y, m.z}, nc[3] = {n.x, n.y, n.z};
    const int face = 2 * axis + (nc[axis] > 0 ? 0 : 1);
    const int u0 = step(mc[(axis + 1) % 3]), v0 = step(mc[(axis + 2) % 3]);
    auto code = [&](int u, int v) { return (face * kNormalSteps + u) * kNormalSteps + v; };
    auto usable = [&](int u, int v) {
      return u >= 0 && v >= 0 && u < kNormalSteps && v < kNormalSteps &&
             decode_normal(code(u, v))[axis] != 0;
    };
    const int q = encode_normal(n);
    ASSERT_EQ(q / (kNormalSteps * kNormalSteps), face);
    const int u = q / kNormalSteps % kNormalSteps, v = q % kNormalSteps;
    ASSERT_LE(std::abs(u - u0), 1);
    ASSERT_LE(std::abs(v - v0), 1);
    ASSERT_TRUE(usable(u, v));
    const float chosen = dot(decode_normal(q), m);
    if (q != code(u0, v0) && usable(u0, v0)) {
      EXPECT_GT(chosen, dot(decode_normal(code(u0, v0)), m));
    }
    for (int du = -1; du <= 1; ++du)
      for (int dv = -1; dv <= 1; ++dv) {
        if (usable(u0 + du, v0 + dv)) {
          ASSERT_GE(chosen, dot(decode_normal(code(u0 + du, v0 + dv)), m));
        }
      }
    ++checked;
  }
  EXPECT_GT(checked, 199000);
}

TEST(QSplatCodes, ConeBoundsTheSineOfTheHalfWidth) {
  EXPECT_EQ(encode_cone(0), 0);
  EXPECT_EQ(encode_cone(1.6), 3);
  EXPECT_EQ(encode_cone(M_PI), 3);
  for (double t = 0; t < 1.5; t += 0.001) {
    const int c = encode_cone(t);
    if (c < 3) {
      EXPECT_LT(std::sin(t), decode_cone_sine(c)) << t;
    }
  }
  EXPECT_EQ(decode_cone_sine(3), 1.0f);
}

TEST(QSplatCodes, Rgb565TakesTheNearestCode) {
  const auto five = [](int q) { return q << 3 | q >> 2; };
  const auto six = [](int q) { return q << 2 | q >> 4; };
  for (int v = 0; v < 256; ++v) {
    const auto c = static_cast<uint8_t>(v);
    const uint16_t w = encode_rgb565({c, c, c});
    const auto d = decode_rgb565(w);
    EXPECT_LE(std::abs(d[0] - v), 4);
    EXPECT_LE(std::abs(d[1] - v), 2);
    EXPECT_EQ(d[2], d[0]);
    for (int q = 0; q < 32; ++q) EXPECT_LE(std::abs(d[0] - v), std::abs(five(q) - v)) << v;
    for (int q = 0; q < 64; ++q) EXPECT_LE(std::abs(d[1] - v), std::abs(six(q) - v)) << v;
  }
  EXPECT_EQ(encode_rgb565({255, 255, 255}), 0xFFFF);
  EXPECT_EQ(encode_rgb565({255, 0, 0}), 0xF800);
  EXPECT_EQ(encode_rgb565({0, 255, 0}), 0x07E0);
  const auto w = decode_rgb565(0xFFFF);
  EXPECT_EQ(w[0], 255);
  EXPECT_EQ(w[1], 255);
}

}  // namespace
}  // namespace splatkit::qsplat
