#include "splatkit/synthetic_shapes.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <variant>

#include "splatkit/deterministic_rng.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

constexpr double kPi = std::numbers::pi;

// Every shape is a list of patches of two kinds: planar regions (a polygon minus discs) and
// surfaces of revolution (a segment or circular arc swept around an axis: cylinders, discs,
// spheres, tori). Geometry is computed in double and rounded to float once per point.
struct D2 {
  double u = 0, v = 0;
};
struct D3 {
  double x = 0, y = 0, z = 0;
  D3 operator+(const D3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  D3 operator-(const D3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  D3 operator*(double s) const { return {x * s, y * s, z * s}; }
};
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(const D3& a) { return std::sqrt(dot(a, a)); }
D3 to_d3(const Vec3f& p) { return {p.x, p.y, p.z}; }

struct Circle2 {
  D2 centre;
  double radius = 0;
};

// Points origin + u·a + v·b for (u, v) inside `polygon` and outside every hole; b = normal × a.
struct PlanarRegion {
  D3 origin, normal, a, b;
  std::vector<D2> polygon;
  std::vector<Circle2> holes;  // disjoint discs inside the polygon
};

// The profile (rho, z) swept around `axis` through `centre`: rho = distance from the axis.
// Segment: from p0 to p1. Arc: arc_centre + arc_radius·(cos θ, sin θ) for θ in [theta0, theta1].
// The profile normal is normal_sign·(dz, −drho) along a segment and normal_sign·(cos θ, sin θ) on
// an arc; signs are chosen so that normals point out of the solid.
struct Revolution {
  D3 centre, axis, e1, e2;  // e1, e2, axis orthonormal
  bool is_arc = false;
  D2 p0, p1;
  D2 arc_centre;
  double arc_radius = 0, theta0 = 0, theta1 = 0;
  double normal_sign = 1;
};

struct Patch {
  std::string name;
  std::variant<PlanarRegion, Revolution> surface;
};

// A crease: a segment a–b, or a circle (centre, axis, radius).
struct Crease {
  bool is_circle = false;
  D3 a, b;
  D3 centre, axis;
  double radius = 0;
};

struct ShapeModel {
  std::vector<Patch> patches;
  std::vector<Crease> creases;
  D3 min, max;  // analytic bounds
};

// ---- planar regions ----------------------------------------------------------------------------

PlanarRegion make_plane(D3 origin, D3 normal, D3 a, std::vector<D2> polygon,
                        std::vector<Circle2> holes = {}) {
  return {origin, normal, a, cross(normal, a), std::move(polygon), std::move(holes)};
}

D3 plane_point(const PlanarRegion& r, D2 q) { return r.origin + r.a * q.u + r.b * q.v; }

bool inside_polygon(const std::vector<D2>& poly, D2 q) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const D2 &p = poly[i], &s = poly[j];
    if ((p.v > q.v) != (s.v > q.v) && q.u < p.u + (q.v - p.v) * (s.u - p.u) / (s.v - p.v))
      inside = !inside;
  }
  return inside;
}

bool inside_region(const PlanarRegion& r, D2 q) {
  if (!inside_polygon(r.polygon, q)) return false;
  for (const Circle2& c : r.holes)
    if (std::hypot(q.u - c.centre.u, q.v - c.centre.v) < c.radius) return false;
  return true;
}

double region_area(const PlanarRegion& r) {
  double twice = 0;
  for (std::size_t i = 0, j = r.polygon.size() - 1; i < r.polygon.size(); j = i++)
    twice += r.polygon[j].u * r.polygon[i].v - r.polygon[i].u * r.polygon[j].v;
  double area = std::abs(twice) / 2;
  for (const Circle2& c : r.holes) area -= kPi * c.radius * c.radius;
  return area;
}

double distance_2d_to_segment(D2 q, D2 a, D2 b) {
  const double du = b.u - a.u, dv = b.v - a.v;
  const double len2 = du * du + dv * dv;
  double t = len2 > 0 ? ((q.u - a.u) * du + (q.v - a.v) * dv) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(q.u - a.u - t * du, q.v - a.v - t * dv);
}

double distance_to_planar(const PlanarRegion& r, const D3& p) {
  const D3 d = p - r.origin;
  const D2 q{dot(d, r.a), dot(d, r.b)};
  const double height = dot(d, r.normal);
  if (inside_region(r, q)) return std::abs(height);
  // Outside the region the nearest region point lies on its boundary: an edge or a hole circle.
  double in_plane = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = r.polygon.size() - 1; i < r.polygon.size(); j = i++)
    in_plane = std::min(in_plane, distance_2d_to_segment(q, r.polygon[j], r.polygon[i]));
  for (const Circle2& c : r.holes)
    in_plane =
        std::min(in_plane, std::abs(std::hypot(q.u - c.centre.u, q.v - c.centre.v) - c.radius));
  return std::hypot(height, in_plane);
}

// The parts of the line v = const inside the region, as sorted disjoint [u0, u1] intervals.
std::vector<std::pair<double, double>> scanline(const PlanarRegion& r, double v) {
  std::vector<double> cuts;
  for (std::size_t i = 0, j = r.polygon.size() - 1; i < r.polygon.size(); j = i++) {
    const D2 &p = r.polygon[i], &s = r.polygon[j];
    if ((p.v > v) != (s.v > v)) cuts.push_back(p.u + (v - p.v) * (s.u - p.u) / (s.v - p.v));
  }
  std::sort(cuts.begin(), cuts.end());
  std::vector<std::pair<double, double>> spans;
  for (std::size_t i = 0; i + 1 < cuts.size(); i += 2) spans.emplace_back(cuts[i], cuts[i + 1]);
  for (const Circle2& c : r.holes) {
    const double dv = v - c.centre.v;
    if (std::abs(dv) >= c.radius) continue;
    const double half = std::sqrt(c.radius * c.radius - dv * dv);
    const double lo = c.centre.u - half, hi = c.centre.u + half;
    std::vector<std::pair<double, double>> kept;
    for (auto [a, b] : spans) {
      if (a < lo) kept.emplace_back(a, std::min(b, lo));
      if (b > hi) kept.emplace_back(std::max(a, hi), b);
    }
    spans = std::move(kept);
  }
  return spans;
}

// ---- surfaces of revolution --------------------------------------------------------------------

double profile_length(const Revolution& r) {
  if (r.is_arc) return r.arc_radius * (r.theta1 - r.theta0);
  return std::hypot(r.p1.u - r.p0.u, r.p1.v - r.p0.v);
}

// Profile point (rho, z) and unit profile normal at arc length t.
std::pair<D2, D2> profile_at(const Revolution& r, double t) {
  if (r.is_arc) {
    const double th = r.theta0 + t / r.arc_radius;
    const double c = std::cos(th), s = std::sin(th);
    return {{r.arc_centre.u + r.arc_radius * c, r.arc_centre.v + r.arc_radius * s},
            {r.normal_sign * c, r.normal_sign * s}};
  }
  const double len = profile_length(r);
  const double du = (r.p1.u - r.p0.u) / len, dv = (r.p1.v - r.p0.v) / len;
  return {{r.p0.u + du * t, r.p0.v + dv * t}, {r.normal_sign * dv, -r.normal_sign * du}};
}

double rho_at(const Revolution& r, double t) { return profile_at(r, t).first.u; }

// Area of the band swept by the profile between arc lengths t0 and t1: 2π ∫ rho dt.
double band_area(const Revolution& r, double t0, double t1) {
  if (!r.is_arc) return kPi * (rho_at(r, t0) + rho_at(r, t1)) * (t1 - t0);
  const double a = r.arc_radius;
  const double th0 = r.theta0 + t0 / a, th1 = r.theta0 + t1 / a;
  return 2 * kPi * a * (r.arc_centre.u * (th1 - th0) + a * (std::sin(th1) - std::sin(th0)));
}

double max_rho(const Revolution& r, double t0, double t1) {
  double m = std::max(rho_at(r, t0), rho_at(r, t1));
  if (r.is_arc) {
    const double th0 = r.theta0 + t0 / r.arc_radius, th1 = r.theta0 + t1 / r.arc_radius;
    if (th0 <= 0 && th1 >= 0) m = r.arc_centre.u + r.arc_radius;  // cos θ peaks at θ = 0
  }
  return m;
}

void revolution_point(const Revolution& r, double t, double phi, D3* p, D3* n) {
  const auto [q, qn] = profile_at(r, t);
  const D3 radial = r.e1 * std::cos(phi) + r.e2 * std::sin(phi);
  *p = r.centre + (r.axis * q.v + radial * q.u);
  *n = r.axis * qn.v + radial * qn.u;
}

double distance_to_revolution(const Revolution& r, const D3& p) {
  const D3 d = p - r.centre;
  const double z = dot(d, r.axis);
  const D2 q{length(d - r.axis * z), z};
  if (!r.is_arc) return distance_2d_to_segment(q, r.p0, r.p1);
  const double du = q.u - r.arc_centre.u, dv = q.v - r.arc_centre.v;
  const double th = std::atan2(dv, du);
  if (th >= r.theta0 && th <= r.theta1) return std::abs(std::hypot(du, dv) - r.arc_radius);
  const D2 e0 = profile_at(r, 0).first, e1 = profile_at(r, profile_length(r)).first;
  return std::min(std::hypot(q.u - e0.u, q.v - e0.v), std::hypot(q.u - e1.u, q.v - e1.v));
}

// ---- the shapes --------------------------------------------------------------------------------

const D3 kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

Revolution make_revolution(D3 centre, D3 axis, D3 e1) {
  Revolution r;
  r.centre = centre;
  r.axis = axis;
  r.e1 = e1;
  r.e2 = cross(axis, e1);
  return r;
}

Revolution sweep_segment(D3 centre, D3 axis, D3 e1, D2 p0, D2 p1, double normal_sign) {
  Revolution r = make_revolution(centre, axis, e1);
  r.p0 = p0;
  r.p1 = p1;
  r.normal_sign = normal_sign;
  return r;
}

Revolution sweep_arc(D3 centre, D3 axis, D3 e1, D2 arc_centre, double radius, double theta0,
                     double theta1) {
  Revolution r = make_revolution(centre, axis, e1);
  r.is_arc = true;
  r.arc_centre = arc_centre;
  r.arc_radius = radius;
  r.theta0 = theta0;
  r.theta1 = theta1;
  return r;
}

Crease segment_crease(D3 a, D3 b) { return {false, a, b, {}, {}, 0}; }
Crease circle_crease(D3 centre, D3 axis, double radius) {
  return {true, {}, {}, centre, axis, radius};
}

ShapeModel make_sphere() {
  ShapeModel m;
  m.patches.push_back({"sphere", sweep_arc({0, 0, 0}, kZ, kX, {0, 0}, 1, -kPi / 2, kPi / 2)});
  m.min = {-1, -1, -1};
  m.max = {1, 1, 1};
  return m;
}

constexpr double kTorusMajor = 1.0, kTorusMinor = 0.35;

ShapeModel make_torus() {
  ShapeModel m;
  m.patches.push_back(
      {"torus", sweep_arc({0, 0, 0}, kZ, kX, {kTorusMajor, 0}, kTorusMinor, -kPi, kPi)});
  const double e = kTorusMajor + kTorusMinor;
  m.min = {-e, -e, -kTorusMinor};
  m.max = {e, e, kTorusMinor};
  return m;
}

// Centres at x = ∓0.6; the spheres cross on the circle x = 0, radius 0.8. Each sphere is an arc
// about its own axis pointing at the other sphere, so dropping the part inside the other sphere
// (local height > 0.6) only shortens the arc and the crease circle is a row boundary.
constexpr double kSphereOffset = 0.6;

ShapeModel make_two_spheres(bool keep_inside) {
  ShapeModel m;
  const double top = keep_inside ? kPi / 2 : std::asin(kSphereOffset);
  m.patches.push_back(
      {"red-sphere", sweep_arc({-kSphereOffset, 0, 0}, kX, kY, {0, 0}, 1, -kPi / 2, top)});
  m.patches.push_back(
      {"blue-sphere", sweep_arc({kSphereOffset, 0, 0}, kX * -1, kY, {0, 0}, 1, -kPi / 2, top)});
  m.creases.push_back(circle_crease({0, 0, 0}, kX, std::sqrt(1 - kSphereOffset * kSphereOffset)));
  m.min = {-1 - kSphereOffset, -1, -1};
  m.max = {1 + kSphereOffset, 1, 1};
  return m;
}

ShapeModel make_cube() {
  ShapeModel m;
  const D3 axes[3] = {kX, kY, kZ};
  const char* names[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
  const std::vector<D2> square = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int k = 0; k < 3; ++k)
    for (int side = 0; side < 2; ++side) {
      const D3 n = axes[k] * (side == 0 ? -1.0 : 1.0);
      m.patches.push_back({names[2 * k + side], make_plane(n, n, axes[(k + 1) % 3], square)});
    }
  for (int k = 0; k < 3; ++k)
    for (double s : {-1.0, 1.0})
      for (double t : {-1.0, 1.0}) {
        const D3 offset = axes[(k + 1) % 3] * s + axes[(k + 2) % 3] * t;
        m.creases.push_back(segment_crease(offset - axes[k], offset + axes[k]));
      }
  m.min = {-1, -1, -1};
  m.max = {1, 1, 1};
  return m;
}

// The CAD-like part: a prism along y (|y| ≤ 1) whose profile in the xz-plane runs (−1.5, 0),
// (1.5, 0), (kTopEnd, H), (−1.5, H): the +x face is a bevel meeting the bottom at a 60° dihedral
// angle and the top at 120°; every other prism edge is 90°. A cylindrical boss (radius 0.4,
// height 0.5) stands on the top (a concave 90° crease at its foot, convex 90° at its rim), and a
// cylindrical hole (radius 0.25) goes through from top to bottom (convex 90° rims).
constexpr double kHalfWidth = 1.5, kHalfDepth = 1.0, kHeight = 1.2;
const double kTopEnd = kHalfWidth - kHeight / std::sqrt(3.0);
constexpr double kBossX = -0.7, kBossRadius = 0.4, kBossHeight = 0.5;
constexpr double kHoleX = 0.2, kHoleRadius = 0.25;

void add_cad_creases(ShapeModel& m) {
  const D2 profile[4] = {
      {-kHalfWidth, 0}, {kHalfWidth, 0}, {kTopEnd, kHeight}, {-kHalfWidth, kHeight}};
  auto at = [](D2 q, double y) { return D3{q.u, y, q.v}; };
  for (int i = 0; i < 4; ++i) {
    const D2 p = profile[i], q = profile[(i + 1) % 4];
    m.creases.push_back(segment_crease(at(p, -kHalfDepth), at(p, kHalfDepth)));
    m.creases.push_back(segment_crease(at(p, -kHalfDepth), at(q, -kHalfDepth)));
    m.creases.push_back(segment_crease(at(p, kHalfDepth), at(q, kHalfDepth)));
  }
  m.creases.push_back(circle_crease({kBossX, 0, kHeight}, kZ, kBossRadius));
  m.creases.push_back(circle_crease({kBossX, 0, kHeight + kBossHeight}, kZ, kBossRadius));
  m.creases.push_back(circle_crease({kHoleX, 0, kHeight}, kZ, kHoleRadius));
  m.creases.push_back(circle_crease({kHoleX, 0, 0}, kZ, kHoleRadius));
}

ShapeModel make_cad_part() {
  ShapeModel m;
  const double slope_length = kHeight / std::sin(kPi / 3);
  const D3 slope_normal{std::sin(kPi / 3), 0, std::cos(kPi / 3)};
  const Circle2 hole{{kHoleX, 0}, kHoleRadius}, boss{{kBossX, 0}, kBossRadius};
  // (u, v) = (x, −y) on the bottom, (x, y) on the top: the hole and boss sit at v = 0 either way.
  m.patches.push_back({"bottom", make_plane({0, 0, 0}, kZ * -1, kX,
                                            {{-kHalfWidth, -kHalfDepth},
                                             {kHalfWidth, -kHalfDepth},
                                             {kHalfWidth, kHalfDepth},
                                             {-kHalfWidth, kHalfDepth}},
                                            {hole})});
  m.patches.push_back({"top", make_plane({0, 0, kHeight}, kZ, kX,
                                         {{-kHalfWidth, -kHalfDepth},
                                          {kTopEnd, -kHalfDepth},
                                          {kTopEnd, kHalfDepth},
                                          {-kHalfWidth, kHalfDepth}},
                                         {boss, hole})});
  m.patches.push_back(
      {"left",
       make_plane(
           {-kHalfWidth, 0, 0}, kX * -1, kZ,
           {{0, -kHalfDepth}, {kHeight, -kHalfDepth}, {kHeight, kHalfDepth}, {0, kHalfDepth}})});
  m.patches.push_back({"bevel", make_plane({kHalfWidth, 0, 0}, slope_normal, kY,
                                           {{-kHalfDepth, 0},
                                            {kHalfDepth, 0},
                                            {kHalfDepth, slope_length},
                                            {-kHalfDepth, slope_length}})});
  const std::vector<D2> front = {
      {-kHalfWidth, 0}, {kHalfWidth, 0}, {kTopEnd, kHeight}, {-kHalfWidth, kHeight}};
  std::vector<D2> back;  // (u, v) = (z, x) on the back face
  for (const D2& q : front) back.push_back({q.v, q.u});
  m.patches.push_back({"front", make_plane({0, -kHalfDepth, 0}, kY * -1, kX, front)});
  m.patches.push_back({"back", make_plane({0, kHalfDepth, 0}, kY, kZ, back)});
  m.patches.push_back({"boss-side", sweep_segment({kBossX, 0, 0}, kZ, kX, {kBossRadius, kHeight},
                                                  {kBossRadius, kHeight + kBossHeight}, 1)});
  m.patches.push_back(
      {"boss-top", sweep_segment({kBossX, 0, 0}, kZ, kX, {kBossRadius, kHeight + kBossHeight},
                                 {0, kHeight + kBossHeight}, 1)});
  m.patches.push_back({"hole", sweep_segment({kHoleX, 0, 0}, kZ, kX, {kHoleRadius, 0},
                                             {kHoleRadius, kHeight}, -1)});
  add_cad_creases(m);
  m.min = {-kHalfWidth, -kHalfDepth, 0};
  m.max = {kHalfWidth, kHalfDepth, kHeight + kBossHeight};
  return m;
}

ShapeModel make_model(ShapeKind kind, bool keep_inside) {
  switch (kind) {
    case ShapeKind::kSphere:
      return make_sphere();
    case ShapeKind::kTorus:
      return make_torus();
    case ShapeKind::kCadPart:
      return make_cad_part();
    case ShapeKind::kTwoSpheres:
      return make_two_spheres(keep_inside);
    case ShapeKind::kCube:
      return make_cube();
  }
  throw std::logic_error("synthetic shapes: unknown kind");
}

// The models are immutable: built once (thread-safe static initialisation), so that per-point
// queries such as distance_to_crease() cost no allocation.
const ShapeModel& model_for(ShapeKind kind, bool keep_inside) {
  static const std::vector<ShapeModel> models = [] {
    std::vector<ShapeModel> all;  // in ShapeKind's declaration order, then keep_inside
    for (ShapeKind k : {ShapeKind::kSphere, ShapeKind::kTorus, ShapeKind::kCadPart,
                        ShapeKind::kTwoSpheres, ShapeKind::kCube})
      for (bool inside : {false, true}) all.push_back(make_model(k, inside));
    return all;
  }();
  return models.at(2 * static_cast<std::size_t>(kind) + (keep_inside ? 1 : 0));
}

double patch_area(const Patch& p) {
  if (const auto* r = std::get_if<PlanarRegion>(&p.surface)) return region_area(*r);
  const auto& rev = std::get<Revolution>(p.surface);
  return band_area(rev, 0, profile_length(rev));
}

double distance_to(const Patch& p, const D3& q) {
  if (const auto* r = std::get_if<PlanarRegion>(&p.surface)) return distance_to_planar(*r, q);
  return distance_to_revolution(std::get<Revolution>(p.surface), q);
}

double distance_to(const Crease& c, const D3& p) {
  if (c.is_circle) {
    const D3 d = p - c.centre;
    const double h = dot(d, c.axis);
    return std::hypot(h, length(d - c.axis * h) - c.radius);
  }
  const D3 ab = c.b - c.a;
  const double t = std::clamp(dot(p - c.a, ab) / dot(ab, ab), 0.0, 1.0);
  return length(p - (c.a + ab * t));
}

// ---- sampling ----------------------------------------------------------------------------------

// Each cell's one sample falls in the central kJitter fraction of the cell (per axis). Full
// jitter would leave gaps up to √2·h between samples; half jitter bounds the distance from any
// point of a cell to its sample by 0.75 × the cell diagonal (1.06 h for a square cell), barely
// above the 5-NN mean (1.05 h), so a radius of the larger of the two covers the surface.
constexpr double kJitter = 0.5;

// Mean distance to the 5 nearest neighbours, in units of the cell size h = sqrt(area / points).
// Stratified: measured by brute force over large half-jittered samples (a perfect square grid
// gives (4 + √2)/5 = 1.083); tests/unit/test_synthetic_shapes.cpp checks it. Random: the
// Poisson-process expectation Σ_{k=1..5} Γ(k + ½)/Γ(k) / (5√π) = 0.902.
constexpr double kStratifiedKnnRadius = 1.05;
// A Poisson sample leaves a fraction exp(−π r²/h²) of the surface uncovered by discs of radius r;
// r = h·sqrt(ln(10⁴)/π) leaves 10⁻⁴ (the 5-NN mean 0.902 h would leave 7.8 %).
const double kRandomRadius = std::sqrt(std::log(1e4) / kPi);

// Receives a sample: exact position, exact unit normal, the distance within which it covers its
// own cell, and its patch.
using Emit = std::function<void(const D3& p, const D3& n, double cover, uint32_t patch)>;

int stochastic_round(double x, DeterministicRng& rng) {
  return static_cast<int>(std::floor(x + rng.uniform()));
}

double jittered(double lo, double size, DeterministicRng& rng) {
  return lo + size * (0.5 + kJitter * (rng.uniform() - 0.5));
}

void sample_planar_stratified(const PlanarRegion& r, double h, uint32_t patch,
                              DeterministicRng& rng, const Emit& emit) {
  double vmin = r.polygon[0].v, vmax = vmin;
  for (const D2& q : r.polygon) vmin = std::min(vmin, q.v), vmax = std::max(vmax, q.v);
  const int rows = std::max(1, static_cast<int>(std::lround((vmax - vmin) / h)));
  const double row_height = (vmax - vmin) / rows;
  for (int k = 0; k < rows; ++k) {
    const double v0 = vmin + k * row_height;
    for (auto [u0, u1] : scanline(r, v0 + row_height / 2)) {
      const int cells = stochastic_round((u1 - u0) * row_height / (h * h), rng);
      if (cells <= 0) continue;
      const double w = (u1 - u0) / cells;
      const double cover = 0.5 * (1 + kJitter) * std::hypot(w, row_height);
      for (int i = 0; i < cells; ++i) {
        D2 q{jittered(u0 + i * w, w, rng), jittered(v0, row_height, rng)};
        if (inside_region(r, q)) {
          emit(plane_point(r, q), r.normal, cover, patch);
          continue;
        }
        // Near a slanted edge or a hole the central part of a cell can fall outside the region:
        // retry anywhere in the cell (the sample then covers its cell from up to a diagonal
        // away), and give up on cells that are (almost) all outside.
        for (int tries = 0; tries < 16 && !inside_region(r, q); ++tries)
          q = {u0 + (i + rng.uniform()) * w, v0 + rng.uniform() * row_height};
        if (inside_region(r, q))
          emit(plane_point(r, q), r.normal, std::hypot(w, row_height), patch);
      }
    }
  }
}

// Arc length in [t0, t1] with density ∝ rho (area-uniform on the band), by rejection.
double sample_profile(const Revolution& r, double t0, double t1, DeterministicRng& rng) {
  const double rho_max = max_rho(r, t0, t1);
  double t = t0;
  for (int tries = 0; tries < 64; ++tries) {
    t = rng.uniform(t0, t1);
    if (rho_max <= 0 || rng.uniform() * rho_max <= rho_at(r, t)) break;
  }
  return t;
}

// Farthest distance from a point of the cell [t0, t1] × [0, dphi] to a point of its central
// kJitter part (where the sample lands), over a grid that includes corners and edge midpoints.
double cell_cover(const Revolution& r, double t0, double t1, double dphi) {
  double worst = 0;
  D3 n;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) {
      D3 p;
      revolution_point(r, t0 + (t1 - t0) * i / 4, dphi * j / 4, &p, &n);
      for (int a = 0; a <= 2; ++a)
        for (int b = 0; b <= 2; ++b) {
          D3 s;
          revolution_point(r, t0 + (t1 - t0) * (0.5 + kJitter * (a / 2.0 - 0.5)),
                           dphi * (0.5 + kJitter * (b / 2.0 - 0.5)), &s, &n);
          worst = std::max(worst, length(p - s));
        }
    }
  return worst;
}

void sample_revolution_stratified(const Revolution& r, double h, uint32_t patch,
                                  DeterministicRng& rng, const Emit& emit) {
  const double total = profile_length(r);
  const int rows = std::max(1, static_cast<int>(std::lround(total / h)));
  const double row_height = total / rows;
  for (int k = 0; k < rows; ++k) {
    const double t0 = k * row_height, t1 = t0 + row_height;
    const int cells = stochastic_round(band_area(r, t0, t1) / (h * h), rng);
    if (cells <= 0) continue;
    const double dphi = 2 * kPi / cells;
    const double phase = rng.uniform() * dphi;  // rows start at random angles: no seam
    const double cover = cell_cover(r, t0, t1, dphi);
    const double lo = t0 + row_height * (1 - kJitter) / 2, hi = t0 + row_height * (1 + kJitter) / 2;
    for (int i = 0; i < cells; ++i) {
      const double phi = jittered(phase + i * dphi, dphi, rng);
      D3 p, n;
      revolution_point(r, sample_profile(r, lo, hi, rng), phi, &p, &n);
      emit(p, n, cover, patch);
    }
  }
}

// The middle of the band of width `spacing` (counted from `origin`) that x falls in; x itself for
// spacing 0.
double band_middle(double x, double origin, double spacing) {
  return spacing > 0 ? origin + (std::floor((x - origin) / spacing) + 0.5) * spacing : x;
}

// One area-uniform sample of the patch; with line_spacing > 0, moved across to the middle of its
// scan line's band (planes: v; surfaces of revolution: the profile position t).
void sample_uniform(const Patch& patch, uint32_t id, double line_spacing, DeterministicRng& rng,
                    const Emit& emit) {
  if (const auto* r = std::get_if<PlanarRegion>(&patch.surface)) {
    D2 lo = r->polygon[0], hi = lo;
    for (const D2& q : r->polygon) {
      lo = {std::min(lo.u, q.u), std::min(lo.v, q.v)};
      hi = {std::max(hi.u, q.u), std::max(hi.v, q.v)};
    }
    D2 q;
    do {
      q = {rng.uniform(lo.u, hi.u), rng.uniform(lo.v, hi.v)};
      q.v = band_middle(q.v, lo.v, line_spacing);
    } while (!inside_region(*r, q));
    emit(plane_point(*r, q), r->normal, 0, id);
    return;
  }
  const auto& rev = std::get<Revolution>(patch.surface);
  D3 p, n;
  const double length = profile_length(rev);
  const double t =
      std::min(band_middle(sample_profile(rev, 0, length, rng), 0, line_spacing), length);
  revolution_point(rev, t, rng.uniform(0, 2 * kPi), &p, &n);
  emit(p, n, 0, id);
}

// Adding +0.0 turns −0.0 into +0.0, so text outputs never show "-0".
Vec3f to_float(const D3& p) {
  return {static_cast<float>(p.x + 0.0), static_cast<float>(p.y + 0.0),
          static_cast<float>(p.z + 0.0)};
}

void check_options(const ShapeOptions& o) {
  if (o.points == 0) throw_usage("synthetic shape: the number of points must be at least 1");
  if (o.points > (std::size_t{1} << 30))
    throw_usage("synthetic shape: at most 2^30 points (asked for " + std::to_string(o.points) +
                ")");
  if (!std::isfinite(o.noise) || o.noise < 0)
    throw_usage("synthetic shape: noise must be a finite number >= 0");
  if (!(o.scan_lines >= 0 && o.scan_lines <= 1000))
    throw_usage("synthetic shape: scan lines' anisotropy must be in [0, 1000]");
}

}  // namespace

SplatCloud make_shape(const ShapeOptions& options) {
  check_options(options);
  const ShapeModel& model = model_for(options.kind, options.keep_inside);
  std::vector<double> areas;
  double total_area = 0;
  for (const Patch& p : model.patches) total_area += areas.emplace_back(patch_area(p));
  const double h = std::sqrt(total_area / static_cast<double>(options.points));
  const double sigma = options.noise * length(model.max - model.min);
  const bool lines = options.scan_lines > 1;
  const bool random = options.random || lines;
  const double line_spacing = lines ? h * std::sqrt(options.scan_lines) : 0;
  const double base_radius = h * (random ? kRandomRadius : kStratifiedKnnRadius) *
                             (lines ? std::sqrt(options.scan_lines) : 1.0);

  SplatCloud cloud;
  ExtraAttribute patch_ids{"patch_id", ScalarType::kUInt32};
  const std::size_t expected = options.points + options.points / 50 + 16;  // stratified rounding
  cloud.positions.reserve(expected);
  cloud.normals.reserve(expected);
  cloud.radii.reserve(expected);
  cloud.colors.reserve(expected);
  patch_ids.values.reserve(expected);
  DeterministicRng noise_rng(options.seed, 0x6E6F697365ull);
  const bool two_colours = options.kind == ShapeKind::kTwoSpheres;
  // --texture: its own random stream, so that positions do not change with it.
  DeterministicRng texture_rng(options.seed, 0x74657874ull);
  ExtraAttribute intensity{"intensity", ScalarType::kUInt16};
  if (options.texture) intensity.values.reserve(expected);
  const double wave = 2 * M_PI * 3 / length(model.max - model.min);  // 3 periods across
  auto textured = [&](const D3& p, std::array<uint16_t, 3>& rgb) {
    const double t = std::sin(p.x * wave) + std::cos(p.y * wave * 1.3) + std::sin(p.z * wave * 0.7);
    const double phase[3] = {0.0, 2.1, 4.2};
    for (int c = 0; c < 3; ++c)
      rgb[c] = static_cast<uint16_t>(
          std::clamp(std::round(128 + 60 * std::sin(1.7 * t + phase[c]) + 6 * texture_rng.normal()),
                     0.0, 255.0));
    intensity.values.push_back(
        std::clamp(std::round(2000 + 800 * t / 3 + 40 * texture_rng.normal()), 0.0, 65535.0));
  };
  const Emit emit = [&](const D3& p, const D3& n, double cover, uint32_t patch) {
    const D3 q = sigma > 0 ? p + n * (sigma * noise_rng.normal()) : p;
    cloud.positions.push_back(to_float(q));
    cloud.normals.push_back(to_float(n));
    cloud.radii.push_back(static_cast<float>(std::max(base_radius, cover)));
    std::array<uint16_t, 3> rgb{200, 200, 200};
    if (options.texture)
      textured(p, rgb);
    else if (two_colours)
      rgb = patch == 0 ? std::array<uint16_t, 3>{255, 0, 0} : std::array<uint16_t, 3>{0, 0, 255};
    cloud.colors.push_back(rgb);
    patch_ids.values.push_back(patch);
  };

  if (random) {
    DeterministicRng rng(options.seed, 0);
    for (std::size_t i = 0; i < options.points; ++i) {
      double pick = rng.uniform() * total_area;
      std::size_t k = 0;
      while (k + 1 < areas.size() && pick >= areas[k]) pick -= areas[k++];
      sample_uniform(model.patches[k], static_cast<uint32_t>(k), line_spacing, rng, emit);
    }
  } else {
    for (std::size_t k = 0; k < model.patches.size(); ++k) {
      DeterministicRng rng(options.seed, k + 1);
      const auto id = static_cast<uint32_t>(k);
      if (const auto* r = std::get_if<PlanarRegion>(&model.patches[k].surface))
        sample_planar_stratified(*r, h, id, rng, emit);
      else
        sample_revolution_stratified(std::get<Revolution>(model.patches[k].surface), h, id, rng,
                                     emit);
    }
  }
  cloud.extras.push_back(std::move(patch_ids));
  if (options.texture) cloud.extras.push_back(std::move(intensity));
  cloud.check_consistent();
  return cloud;
}

ShapeKind parse_shape_kind(const std::string& name) {
  for (ShapeKind k : {ShapeKind::kSphere, ShapeKind::kTorus, ShapeKind::kCadPart,
                      ShapeKind::kTwoSpheres, ShapeKind::kCube})
    if (shape_kind_name(k) == name) return k;
  throw_usage("unknown shape '" + name + "' (expected sphere, torus, cad, two-spheres or cube)");
}

std::string shape_kind_name(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kSphere:
      return "sphere";
    case ShapeKind::kTorus:
      return "torus";
    case ShapeKind::kCadPart:
      return "cad";
    case ShapeKind::kTwoSpheres:
      return "two-spheres";
    case ShapeKind::kCube:
      return "cube";
  }
  return "unknown";
}

float distance_to_crease(ShapeKind kind, const Vec3f& p) {
  const ShapeModel& model = model_for(kind, false);
  double best = std::numeric_limits<double>::infinity();
  for (const Crease& c : model.creases) best = std::min(best, distance_to(c, to_d3(p)));
  return static_cast<float>(best);
}

std::vector<std::string> shape_patch_names(const ShapeOptions& options) {
  std::vector<std::string> names;
  for (const Patch& p : model_for(options.kind, options.keep_inside).patches)
    names.push_back(p.name);
  return names;
}

Bounds shape_bounds(const ShapeOptions& options) {
  const ShapeModel& m = model_for(options.kind, options.keep_inside);
  return {{static_cast<float>(m.min.x), static_cast<float>(m.min.y), static_cast<float>(m.min.z)},
          {static_cast<float>(m.max.x), static_cast<float>(m.max.y), static_cast<float>(m.max.z)}};
}

float distance_to_shape(const ShapeOptions& options, const Vec3f& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Patch& patch : model_for(options.kind, options.keep_inside).patches)
    best = std::min(best, distance_to(patch, to_d3(p)));
  return static_cast<float>(best);
}

float distance_to_patch(const ShapeOptions& options, uint32_t patch, const Vec3f& p) {
  const ShapeModel& m = model_for(options.kind, options.keep_inside);
  return static_cast<float>(distance_to(m.patches.at(patch), to_d3(p)));
}

}  // namespace splatkit
