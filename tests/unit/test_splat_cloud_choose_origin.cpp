// The origin of the local float frame: chosen from the first points, robust to a stray first
// point (the UTM scan that starts with (0, 0, 0)), and unchanged from choose_origin(first point)
// when that point is representative, through every reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "formats/read_cloud.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/position_builder.h"
#include "splatkit/splat_cloud.h"

namespace splatkit {
namespace {

using Point = std::array<double, 3>;

// 10,000 points of a UTM survey (zone 32N: x ~ 500 km, y ~ 5,000 km) on a jittered 0.1 m grid,
// preceded by a stray (0, 0, 0): the case that made 9,900 points exact duplicates.
std::vector<Point> utm_scan_after_zero() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::vector<Point> pts = {{0, 0, 0}};
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      pts.push_back({512345.678 + 0.1 * i + jitter(rng), 5412345.678 + 0.1 * j + jitter(rng),
                     231.5 + jitter(rng)});
  return pts;
}

std::string fixed3(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

// Positions are file coordinates to within float precision of their local value, and distinct.
void expect_faithful(const SplatCloud& c, const std::vector<Point>& truth, double rounding) {
  ASSERT_EQ(c.size(), truth.size());
  std::set<std::tuple<float, float, float>> distinct;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Vec3f& p = c.positions[i];
    distinct.insert({p.x, p.y, p.z});
    for (int k = 0; k < 3; ++k) {
      const double local = p[k];
      const double err = std::fabs(local + c.origin[k] - truth[i][k]);
      // Half a float ulp of the local value plus the text's own rounding.
      const double allowed = std::ldexp(std::fabs(local), -24) + rounding + 1e-9;
      ASSERT_LE(err, allowed) << "point " << i << " axis " << k;
    }
  }
  EXPECT_EQ(distinct.size(), truth.size());
  // The survey points sit near the origin: millimetre precision with plenty to spare.
  for (std::size_t i = 1; i < truth.size(); ++i)
    ASSERT_LT(std::fabs(c.positions[i].y), 2000.0f) << i;
}

TEST(ChooseOriginFromSample, StrayFirstPointDoesNotChooseTheOrigin) {
  const auto pts = utm_scan_after_zero();
  const Point o = choose_origin_from_sample(pts);
  EXPECT_EQ(o, (Point{512000, 5412000, 0}));
}

TEST(ChooseOriginFromSample, RepresentativeFirstPointKeepsItsOwnOrigin) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 9000);  // 9 km wide: crosses 1000 m boundaries
  std::vector<Point> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({650000 + u(rng), 5300000 + u(rng), u(rng) / 20});
  EXPECT_EQ(choose_origin_from_sample(pts), choose_origin(pts[0]));
  // Small coordinates keep the zero origin, a single point its own.
  EXPECT_EQ(choose_origin_from_sample(std::vector<Point>{{1, 2, 3}, {-9000, 5, 5}}),
            (Point{0, 0, 0}));
  EXPECT_EQ(choose_origin_from_sample(std::vector<Point>{{123456.7, 2, 3}}), (Point{123000, 0, 0}));
  EXPECT_EQ(choose_origin_from_sample({}), (Point{0, 0, 0}));
}

TEST(ChooseOriginFromSample, StrayFarFirstPointBeforeSmallCoordinates) {
  std::vector<Point> pts = {{5e6, 5e6, 0}};
  for (int i = 0; i < 50; ++i) pts.push_back({i * 0.5, 1.0, -i * 0.25});
  EXPECT_EQ(choose_origin_from_sample(pts), (Point{0, 0, 0}));
}

TEST(PositionBuilder, ConvertsTheSampleOnceTheOriginIsKnown) {
  const auto pts = utm_scan_after_zero();
  SplatCloud c;
  PositionBuilder b(c, "t.xyz");
  for (const Point& p : pts) b.add(p);
  EXPECT_EQ(b.size(), pts.size());
  b.finish();
  expect_faithful(c, pts, 0);
}

TEST(ChooseOriginFromSample, UtmScanAfterZeroThroughXyz) {
  const auto pts = utm_scan_after_zero();
  std::string s;
  for (const Point& p : pts) s += fixed3(p[0]) + " " + fixed3(p[1]) + " " + fixed3(p[2]) + "\n";
  InputStream in("utm.xyz", s.data(), s.size());
  expect_faithful(read_cloud(in).cloud, pts, 0.0005);
}

TEST(ChooseOriginFromSample, UtmScanAfterZeroThroughOff) {
  const auto pts = utm_scan_after_zero();
  std::string s = "OFF\n" + std::to_string(pts.size()) + " 0 0\n";
  for (const Point& p : pts) s += fixed3(p[0]) + " " + fixed3(p[1]) + " " + fixed3(p[2]) + "\n";
  InputStream in("utm.off", s.data(), s.size());
  expect_faithful(read_cloud(in).cloud, pts, 0.0005);
}

TEST(ChooseOriginFromSample, UtmScanAfterZeroThroughPlyAsciiAndBinary) {
  const auto pts = utm_scan_after_zero();
  const std::string props = "element vertex " + std::to_string(pts.size()) +
                            "\nproperty double x\nproperty double y\nproperty double z\n"
                            "end_header\n";
  std::string ascii = "ply\nformat ascii 1.0\n" + props;
  std::string binary = "ply\nformat binary_little_endian 1.0\n" + props;
  for (const Point& p : pts) {
    ascii += fixed3(p[0]) + " " + fixed3(p[1]) + " " + fixed3(p[2]) + "\n";
    binary.append(reinterpret_cast<const char*>(p.data()), 24);
  }
  InputStream a("utm.ply", ascii.data(), ascii.size());
  expect_faithful(read_cloud(a).cloud, pts, 0.0005);
  InputStream b("utm.ply", binary.data(), binary.size());
  expect_faithful(read_cloud(b).cloud, pts, 0);
}

// LAS 1.2, point format 0, centimetre scale, offset 0: the stray point is stored as (0, 0, 0).
TEST(ChooseOriginFromSample, UtmScanAfterZeroThroughLas) {
  const auto pts = utm_scan_after_zero();
  std::string s(227, '\0');
  auto put = [&](std::size_t at, const auto& v) { std::memcpy(s.data() + at, &v, sizeof v); };
  std::memcpy(s.data(), "LASF", 4);
  s[24] = 1, s[25] = 2;
  put(94, uint16_t{227});
  put(96, uint32_t{227});
  put(105, uint16_t{20});
  put(107, static_cast<uint32_t>(pts.size()));
  for (int k = 0; k < 3; ++k) put(131 + 8 * k, 0.01);
  std::vector<Point> truth;
  for (const Point& p : pts) {
    std::string r(20, '\0');
    Point q;
    for (int k = 0; k < 3; ++k) {
      const auto raw = static_cast<int32_t>(std::llround(p[k] * 100));
      std::memcpy(r.data() + 4 * k, &raw, 4);
      q[k] = raw * 0.01;
    }
    truth.push_back(q);
    s += r;
  }
  InputStream in("utm.las", s.data(), s.size());
  expect_faithful(read_cloud(in).cloud, truth, 0);
}

}  // namespace
}  // namespace splatkit
