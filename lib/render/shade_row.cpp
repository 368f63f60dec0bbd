#include "render/shade_row.h"

#include <cmath>

namespace splatkit::render {

namespace {

constexpr int kRun = kMaxShadeRun;

// One run as structure of arrays, so that every step below is a loop over lanes.
struct Lanes {
  float x[kRun], y[kRun], z[kRun];
};

// a[i] = normalized(a[i]) as splatkit::normalized computes it (division by the length, zero
// vector for zero length).
inline void normalize_lanes(Lanes& a, int count) {
  for (int i = 0; i < count; ++i) {
    const float len = std::sqrt(a.x[i] * a.x[i] + a.y[i] * a.y[i] + a.z[i] * a.z[i]);
    const bool ok = len > 0;
    a.x[i] = ok ? a.x[i] / len : 0.0f;
    a.y[i] = ok ? a.y[i] / len : 0.0f;
    a.z[i] = ok ? a.z[i] / len : 0.0f;
  }
}

// std::max(0.0f, v) by value (its reference result keeps GCC from vectorising).
inline float max0(float v) { return 0.0f < v ? v : 0.0f; }

// -normalized(projection.ray(x + 0.5, y + 0.5)) for the run's pixels: towards the eye.
void view_lanes(const Projection& pr, int x0, int y, int count, Lanes& v) {
  const float ty = (float(y) + 0.5f - pr.cy) / pr.focal_px;
  for (int i = 0; i < count; ++i) {
    const float tx = (float(x0 + i) + 0.5f - pr.cx) / pr.focal_px;
    v.x[i] = pr.forward.x + pr.right.x * tx + pr.down.x * ty;
    v.y[i] = pr.forward.y + pr.right.y * tx + pr.down.y * ty;
    v.z[i] = pr.forward.z + pr.right.z * tx + pr.down.z * ty;
  }
  normalize_lanes(v, count);
  for (int i = 0; i < count; ++i) {
    v.x[i] = -v.x[i];
    v.y[i] = -v.y[i];
    v.z[i] = -v.z[i];
  }
}

// shade_pixel's Phong branch, step by step over the run.
void phong_row(const Shading& s, const Lanes& v, int count, const PixelSurface* g, Vec3f* colors) {
  Lanes n, h;
  float lambert[kRun], spec[kRun], base[kRun];
  for (int i = 0; i < count; ++i) {
    n.x[i] = g[i].normal.x;
    n.y[i] = g[i].normal.y;
    n.z[i] = g[i].normal.z;
  }
  normalize_lanes(n, count);
  const Vec3f l = s.light;
  for (int i = 0; i < count; ++i) {
    // Two-sided: mirrored in the plane perpendicular to the view (shade_pixel.cpp says why).
    const float nv = n.x[i] * v.x[i] + n.y[i] * v.y[i] + n.z[i] * v.z[i];
    const float t = 2 * nv;
    const bool away = nv < 0;
    n.x[i] = away ? n.x[i] - v.x[i] * t : n.x[i];
    n.y[i] = away ? n.y[i] - v.y[i] * t : n.y[i];
    n.z[i] = away ? n.z[i] - v.z[i] * t : n.z[i];
    lambert[i] = max0(n.x[i] * l.x + n.y[i] * l.y + n.z[i] * l.z);
    h.x[i] = l.x + v.x[i];
    h.y[i] = l.y + v.y[i];
    h.z[i] = l.z + v.z[i];
  }
  normalize_lanes(h, count);
  for (int i = 0; i < count; ++i) {
    base[i] = max0(n.x[i] * h.x[i] + n.y[i] * h.y[i] + n.z[i] * h.z[i]);
    spec[i] = 1.0f;
  }
  // int_pow by squaring, the exponent's bits shared by all lanes.
  for (int e = s.shininess; e > 0; e >>= 1) {
    if (e & 1)
      for (int i = 0; i < count; ++i) spec[i] *= base[i];
    for (int i = 0; i < count; ++i) base[i] *= base[i];
  }
  for (int i = 0; i < count; ++i) {
    const float sp = s.specular * (lambert[i] > 0 ? spec[i] : 0.0f);
    const float k = s.ambient + s.diffuse * lambert[i];
    const Vec3f& a = g[i].albedo;
    colors[i] = {a.x * k + sp, a.y * k + sp, a.z * k + sp};
  }
}

}  // namespace

void shade_row(const Shading& shading, const Projection& projection, int x0, int y, int count,
               const PixelSurface* surfaces, Vec3f* colors) {
  Lanes view;
  view_lanes(projection, x0, y, count, view);
  if (shading.mode == ShadeMode::kPhong) return phong_row(shading, view, count, surfaces, colors);
  for (int i = 0; i < count; ++i) {
    const PixelSurface& s = surfaces[i];
    const Vec3f v{view.x[i], view.y[i], view.z[i]};
    colors[i] = shade_pixel(shading, s.normal, v, s.albedo, s.depth);
  }
}

}  // namespace splatkit::render
