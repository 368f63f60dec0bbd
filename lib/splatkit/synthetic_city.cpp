#include "splatkit/synthetic_city.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace splatkit {

namespace {

constexpr float kPitch = 32;     // block pitch, metres (building footprint + street)
constexpr float kStorey = 3.5f;  // floor-to-floor height
constexpr float kEyeHeight = 1.7f;

struct Building {
  float x0, y0, x1, y1, height;
  std::array<uint16_t, 3> color;
};

struct Rect {
  Vec3f origin, a, b, normal;  // a, b: edges
  std::array<uint16_t, 3> color;
};

float half_extent(int blocks) { return blocks * kPitch / 2; }

std::vector<Building> buildings(const CityOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<float> u01(0, 1);
  std::vector<Building> out;
  const float h = half_extent(o.blocks);
  for (int j = 0; j < o.blocks; ++j)
    for (int i = 0; i < o.blocks; ++i) {
      const float cx = -h + (i + 0.5f) * kPitch, cy = -h + (j + 0.5f) * kPitch;
      const float wx = 16 + 6 * u01(rng), wy = 16 + 6 * u01(rng);
      const int storeys = 3 + int(12 * u01(rng));
      const auto c = [&] { return uint16_t(110 + int(120 * u01(rng))); };
      out.push_back(
          {cx - wx / 2, cy - wy / 2, cx + wx / 2, cy + wy / 2, storeys * kStorey, {c(), c(), c()}});
    }
  return out;
}

// The rectangles of the city, building by building, then the ground in block-sized tiles.
std::vector<Rect> rects(const CityOptions& o) {
  std::vector<Rect> out;
  for (const Building& b : buildings(o)) {
    const float dx = b.x1 - b.x0, dy = b.y1 - b.y0, hz = b.height;
    const auto c = b.color;
    out.push_back({{b.x0, b.y0, 0}, {dx, 0, 0}, {0, 0, hz}, {0, -1, 0}, c});   // south
    out.push_back({{b.x1, b.y1, 0}, {-dx, 0, 0}, {0, 0, hz}, {0, 1, 0}, c});   // north
    out.push_back({{b.x0, b.y1, 0}, {0, -dy, 0}, {0, 0, hz}, {-1, 0, 0}, c});  // west
    out.push_back({{b.x1, b.y0, 0}, {0, dy, 0}, {0, 0, hz}, {1, 0, 0}, c});    // east
    const std::array<uint16_t, 3> roof{90, 80, 75}, floor{200, 190, 170};
    out.push_back({{b.x0, b.y0, hz}, {dx, 0, 0}, {0, dy, 0}, {0, 0, 1}, roof});
    // Floor slabs inside, a little in from the walls.
    for (float z = kStorey; z < hz - 0.5f * kStorey; z += kStorey)
      out.push_back(
          {{b.x0 + 0.3f, b.y0 + 0.3f, z}, {dx - 0.6f, 0, 0}, {0, dy - 0.6f, 0}, {0, 0, 1}, floor});
  }
  const float h = half_extent(o.blocks);
  for (int j = 0; j < o.blocks; ++j)
    for (int i = 0; i < o.blocks; ++i)
      out.push_back({{-h + i * kPitch, -h + j * kPitch, 0},
                     {kPitch, 0, 0},
                     {0, kPitch, 0},
                     {0, 0, 1},
                     {128, 128, 132}});
  return out;
}

}  // namespace

SplatCloud make_city(const CityOptions& o) {
  const std::vector<Rect> all = rects(o);
  double area = 0;
  for (const Rect& r : all) area += norm(r.a) * norm(r.b);
  const float h = float(std::sqrt(area / std::max<std::size_t>(1, o.points)));
  SplatCloud cloud;
  for (const Rect& r : all) {
    const float la = norm(r.a), lb = norm(r.b);
    const int na = std::max(1, int(std::lround(la / h))),
              nb = std::max(1, int(std::lround(lb / h)));
    const float da = la / na, db = lb / nb;
    // Half the cell's diagonal, a little more: every point of the cell is within a disc.
    const float radius = 0.5f * std::sqrt(da * da + db * db) * 1.05f;
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < na; ++i) {
        cloud.positions.push_back(r.origin + r.a * ((i + 0.5f) / na) + r.b * ((j + 0.5f) / nb));
        cloud.normals.push_back(r.normal);
        cloud.radii.push_back(radius);
        cloud.colors.push_back(r.color);
      }
  }
  return cloud;
}

std::vector<CityCamera> city_walkthrough(const CityOptions& o) {
  // Along the street south of the middle row (y between rows blocks/2 − 1 and blocks/2), from the
  // west edge eastwards to the middle cross street, then north along it.
  const float h = half_extent(o.blocks);
  const float street_y = -h + (o.blocks / 2) * kPitch;
  const float cross_x = -h + (o.blocks / 2) * kPitch;
  const float start_x = -h + 0.5f * kPitch;
  const int n = std::max(2, o.walk_frames);
  const int first_leg = n / 2;
  std::vector<CityCamera> out;
  for (int k = 0; k < n; ++k) {
    Vec3f eye, dir;
    if (k < first_leg) {
      const float t = float(k) / std::max(1, first_leg - 1);
      eye = {start_x + t * (cross_x - start_x), street_y, kEyeHeight};
      // Turning towards north over the last fifth of the leg.
      const float turn = std::clamp((t - 0.8f) / 0.2f, 0.0f, 1.0f) * 0.5f;
      dir = {std::cos(turn * 3.14159265f), std::sin(turn * 3.14159265f), 0};
    } else {
      const float t = float(k - first_leg) / std::max(1, n - first_leg - 1);
      eye = {cross_x, street_y + t * (h - 0.5f * kPitch - street_y), kEyeHeight};
      dir = {0, 1, 0};
    }
    out.push_back({eye, eye + dir * 10.0f + Vec3f{0, 0, 0.5f}});
  }
  return out;
}

}  // namespace splatkit
