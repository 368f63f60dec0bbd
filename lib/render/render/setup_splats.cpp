#include "render/setup_splats.h"

#include <algorithm>
#include <cmath>

namespace splatkit::render {

namespace {

// Per-frame constants. Camera-space pixel coordinates are relative to the principal point:
// pixel (i, j) has its centre at X = i + 0.5 - cx, Y = j + 0.5 - cy, and its ray is
// (X / f, Y / f, 1) in camera space.
struct FrameConstants {
  Vec3f eye, right, down, forward;
  float f, inv_f, cx, cy, near;
  int width, height;
};

FrameConstants frame_constants(const Projection& p) {
  return {p.eye, p.right, p.down, p.forward, p.focal_px, 1.0f / p.focal_px,
          p.cx,  p.cy,    p.near, p.width,   p.height};
}

// Branchless orthonormal basis (Duff et al. 2017) for the disc's plane.
inline void disc_axes(const Vec3f& n, Vec3f& a, Vec3f& b) {
  float sign = std::copysign(1.0f, n.z);
  float s = -1.0f / (sign + n.z);
  float t = n.x * n.y * s;
  a = {1.0f + sign * n.x * n.x * s, sign * t, -sign * n.x};
  b = {t, sign + n.y * n.y * s, -n.y};
}

// Extent along one image axis of the projected disc: the tangent lines X = Xc + t of the dual
// conic solve A t² + 2 B t + C = 0, with everything divided by r² and taken relative to the
// projected centre Xc = f c_x / c_z, so that no large terms cancel:
//   A = 1 − n_z² − (c_z / r)²,  B = (1 − n_z²) Xc + f n_x n_z,
//   C = (1 − n_z²) Xc² + 2 f n_x n_z Xc + f² (1 − n_x²).
// Returns the pixels whose centres lie between the two roots, clipped to [0, size).
inline bool pixel_range(float centre, float n_axis, float nz, float one_minus_nz2, float inv_a,
                        float a, float f, float principal, int size, int& lo, int& hi) {
  const float fnn = f * n_axis * nz;
  const float b = one_minus_nz2 * centre + fnn;
  const float c =
      one_minus_nz2 * centre * centre + 2 * fnn * centre + f * f * (1 - n_axis * n_axis);
  const float s = std::sqrt(std::max(0.0f, b * b - a * c));
  // inv_a < 0: (-b - s) * inv_a is the larger root.
  const float mid = principal + centre - b * inv_a;
  const float half = std::fabs(s * inv_a);
  const float first = std::ceil(mid - half - 0.5f), last = std::floor(mid + half - 0.5f);
  if (!(first <= last) || last < 0 || first > float(size - 1)) return false;
  lo = static_cast<int>(std::max(first, 0.0f));
  hi = static_cast<int>(std::min(last, float(size - 1)));
  return true;
}

inline void not_drawn(SplatRaster& s) {
  s.x0 = 1;
  s.x1 = 0;
  s.y0 = s.y1 = 0;
}

// f[0] i + f[1] j + f[2] for w·d(i, j), relative to the box corner (x0, y0).
inline void set_linear(float f[3], const Vec3f& w, const FrameConstants& k, int x0, int y0) {
  f[0] = w.x * k.inv_f;
  f[1] = w.y * k.inv_f;
  f[2] = w.x * ((x0 + 0.5f - k.cx) * k.inv_f) + w.y * ((y0 + 0.5f - k.cy) * k.inv_f) + w.z;
}

}  // namespace

std::size_t setup_splats(const DrawList& draws, const Projection& projection,
                         const SetupOptions& options, std::size_t begin, std::size_t end,
                         SplatRaster* out) {
  const FrameConstants k = frame_constants(projection);
  std::size_t drawn = 0;
  for (std::size_t i = begin; i < end; ++i) {
    SplatRaster& s = out[i - begin];
    const Vec3f cw = draws.positions[i] - k.eye, nw = draws.normals[i];
    const Vec3f c{dot(cw, k.right), dot(cw, k.down), dot(cw, k.forward)};
    const Vec3f n{dot(nw, k.right), dot(nw, k.down), dot(nw, k.forward)};
    const float r = draws.radii[i];
    const float nc = dot(n, c);
    const float one_minus_nz2 = std::max(0.0f, 1.0f - n.z * n.z);
    const float half_depth = r * std::sqrt(one_minus_nz2);
    if (c.z - half_depth <= k.near || (options.cull_backfaces && nc > 0)) {
      not_drawn(s);
      continue;
    }
    const float inv_r = 1.0f / r, inv_z = 1.0f / c.z;
    const float depth_ratio = c.z * inv_r;
    const float a = one_minus_nz2 - depth_ratio * depth_ratio;
    const float inv_a = 1.0f / a;
    int x0, x1, y0, y1;
    if (!pixel_range(k.f * c.x * inv_z, n.x, n.z, one_minus_nz2, inv_a, a, k.f, k.cx, k.width, x0,
                     x1) ||
        !pixel_range(k.f * c.y * inv_z, n.y, n.z, one_minus_nz2, inv_a, a, k.f, k.cy, k.height, y0,
                     y1)) {
      not_drawn(s);
      continue;
    }
    Vec3f ax, ay;
    disc_axes(n, ax, ay);
    const Vec3f wu = (ax * nc - n * dot(ax, c)) * inv_r;
    const Vec3f wv = (ay * nc - n * dot(ay, c)) * inv_r;
    set_linear(s.l, n, k, x0, y0);
    set_linear(s.u, wu, k, x0, y0);
    set_linear(s.v, wv, k, x0, y0);
    s.nc = nc;
    s.zmin = c.z - half_depth;
    s.zmax = c.z + half_depth;
    s.x0 = static_cast<int16_t>(x0);
    s.x1 = static_cast<int16_t>(x1);
    s.y0 = static_cast<int16_t>(y0);
    s.y1 = static_cast<int16_t>(y1);
    ++drawn;
  }
  return drawn;
}

}  // namespace splatkit::render
