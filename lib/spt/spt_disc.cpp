#include "spt/spt_disc.h"

#include <algorithm>
#include <cmath>

namespace splatkit::spt {

namespace {

// An orthonormal pair spanning the plane perpendicular to the unit vector n (deterministic).
void plane_basis(const Vec3f& n, Vec3f& a, Vec3f& b) {
  const Vec3f helper = std::fabs(n.x) < 0.6f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
  a = normalized(cross(helper, n));
  b = cross(n, a);
}

// |v| without overflow for coordinates beyond 1e19 (a far outlier).
float length(const Vec3f& v) {
  return static_cast<float>(std::hypot(double(v.x), double(v.y), double(v.z)));
}

float root_of_rest(float x) { return std::sqrt(std::max(0.0f, 1.0f - x * x)); }

}  // namespace

DiscErrors disc_errors(const SptDisc& p, std::span<const SptDisc> children) {
  DiscErrors e;
  float hi = -INFINITY, lo = INFINITY;
  for (const SptDisc& c : children) {
    const float off = dot(c.centre - p.centre, p.normal);
    const float d = c.radius * root_of_rest(dot(c.normal, p.normal));
    hi = std::max(hi, off + d);
    lo = std::min(lo, off - d);
  }
  e.perpendicular = children.empty() ? 0.0f : hi - lo;
  Vec3f a, b;
  plane_basis(p.normal, a, b);
  constexpr float kHalf = 0.70710678f;
  const Vec3f dirs[8] = {a,  (a + b) * kHalf,  b,  (b - a) * kHalf,
                         -a, (a + b) * -kHalf, -b, (a - b) * kHalf};
  for (const Vec3f& u : dirs) {
    float h = -INFINITY;
    for (const SptDisc& c : children)
      h = std::max(h, dot(u, c.centre - p.centre) + c.radius * root_of_rest(dot(u, c.normal)));
    e.tangential = std::max(e.tangential, p.radius - h);
  }
  return e;
}

SptDisc fit_spt_disc(std::span<const SptDisc> children, float color_weight, bool has_color) {
  double w_sum = 0, cx = 0, cy = 0, cz = 0;
  for (const SptDisc& c : children) w_sum += double(c.radius) * c.radius;
  const bool plain = !(w_sum > 0);
  Vec3f nsum{0, 0, 0}, csum{0, 0, 0};
  std::size_t largest = 0;
  for (std::size_t i = 0; i < children.size(); ++i) {
    const SptDisc& c = children[i];
    const double w = plain ? 1.0 : double(c.radius) * c.radius;
    cx += w * c.centre.x;
    cy += w * c.centre.y;
    cz += w * c.centre.z;
    nsum = nsum + c.normal * static_cast<float>(w);
    csum = csum + c.color * static_cast<float>(w);
    if (c.radius > children[largest].radius) largest = i;
  }
  const double total = plain ? static_cast<double>(children.size()) : w_sum;
  SptDisc p;
  p.centre = {static_cast<float>(cx / total), static_cast<float>(cy / total),
              static_cast<float>(cz / total)};
  const float len = length(nsum);
  p.normal = len > 1e-6f ? nsum * (1 / len) : children[largest].normal;
  for (const SptDisc& c : children) {
    const Vec3f v = c.centre - p.centre;
    const Vec3f t = v - p.normal * dot(v, p.normal);
    p.radius = std::max(p.radius, length(t) + c.radius);
  }
  float color_error = 0;
  if (has_color) {
    p.color = csum * static_cast<float>(1 / total);
    for (const SptDisc& c : children) {
      const Vec3f d = c.color - p.color;
      const float dev = std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}) / 255.0f;
      p.color_deviation = std::max(p.color_deviation, dev + c.color_deviation);
    }
    color_error = color_weight * 2 * p.radius * p.color_deviation;
  }
  const DiscErrors e = disc_errors(p, children);
  p.error = std::hypot(e.perpendicular, e.tangential, color_error);  // no overflow when far apart
  for (const SptDisc& c : children) p.error = std::max(p.error, c.error);
  return p;
}

}  // namespace splatkit::spt
