#include "spt/spt_disc.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace splatkit::spt {

namespace {

// An orthonormal pair spanning the plane perpendicular to the unit vector n (deterministic).
void plane_basis(const Vec3f& n, Vec3f& a, Vec3f& b) {
  const Vec3f helper = std::fabs(n.x) < 0.6f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
  a = normalized(cross(helper, n));
  b = cross(n, a);
}

// |v| without overflow for coordinates beyond 1e19 (a far outlier): squares of floats fit in a
// double.
float length(const Vec3f& v) {
  const double x = v.x, y = v.y, z = v.z;
  return static_cast<float>(std::sqrt(x * x + y * y + z * z));
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
  // h_k = max_i(u_k·(c_i − c) + r_i·√(1 − (u_k·n_i)²)), the 8 directions side by side (the same
  // operations in the same order per direction as one at a time, so the same floats).
  float ux[8], uy[8], uz[8], h[8];
  for (int k = 0; k < 8; ++k) {
    ux[k] = dirs[k].x;
    uy[k] = dirs[k].y;
    uz[k] = dirs[k].z;
    h[k] = -INFINITY;
  }
  for (const SptDisc& c : children) {
    const Vec3f v = c.centre - p.centre;
#if defined(__SSE2__)
    const __m128 vx = _mm_set1_ps(v.x), vy = _mm_set1_ps(v.y), vz = _mm_set1_ps(v.z);
    const __m128 nx = _mm_set1_ps(c.normal.x), ny = _mm_set1_ps(c.normal.y),
                 nz = _mm_set1_ps(c.normal.z), r = _mm_set1_ps(c.radius);
    const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
    for (int k = 0; k < 8; k += 4) {
      const __m128 x = _mm_loadu_ps(ux + k), y = _mm_loadu_ps(uy + k), z = _mm_loadu_ps(uz + k);
      const __m128 along =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, vx), _mm_mul_ps(y, vy)), _mm_mul_ps(z, vz));
      const __m128 t =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, nx), _mm_mul_ps(y, ny)), _mm_mul_ps(z, nz));
      const __m128 rest = _mm_sqrt_ps(_mm_max_ps(zero, _mm_sub_ps(one, _mm_mul_ps(t, t))));
      const __m128 reach = _mm_add_ps(along, _mm_mul_ps(r, rest));
      // max(h, reach) keeping h when they are equal or reach is NaN, as std::max
      const __m128 old = _mm_loadu_ps(h + k);
      _mm_storeu_ps(h + k, _mm_max_ps(reach, old));
    }
#else
    for (int k = 0; k < 8; ++k)
      h[k] = std::max(h[k], dot(dirs[k], v) + c.radius * root_of_rest(dot(dirs[k], c.normal)));
#endif
  }
  for (int k = 0; k < 8; ++k) e.tangential = std::max(e.tangential, p.radius - h[k]);
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
