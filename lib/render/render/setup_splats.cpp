#include "render/setup_splats.h"

#include <algorithm>
#include <cmath>

namespace splatkit::render {

namespace {

// Per-frame constants: the ray through pixel (i, j) is d0 + i·dx + j·dy; the homogeneous pixel
// coordinates of a point p (relative to the eye) are (m0·p, m1·p, m2·p); g = M Mᵀ.
struct FrameConstants {
  Vec3f eye, d0, dx, dy, m0, m1, m2;
  double g00, g02, g11, g12;
  float near;
  int width, height;
};

FrameConstants frame_constants(const Projection& p) {
  FrameConstants k;
  k.eye = p.eye;
  k.dx = p.right / p.focal_px;
  k.dy = p.down / p.focal_px;
  k.d0 = p.ray(0.5f, 0.5f);
  k.m0 = p.right * p.focal_px + p.forward * p.cx;
  k.m1 = p.down * p.focal_px + p.forward * p.cy;
  k.m2 = p.forward;
  double f2 = double(p.focal_px) * p.focal_px;
  k.g00 = f2 + double(p.cx) * p.cx;
  k.g02 = p.cx;
  k.g11 = f2 + double(p.cy) * p.cy;
  k.g12 = p.cy;
  k.near = p.near;
  k.width = p.width;
  k.height = p.height;
  return k;
}

// Branchless orthonormal basis (Duff et al. 2017) for the disc's plane.
inline void disc_axes(const Vec3f& n, Vec3f& a, Vec3f& b) {
  float sign = std::copysign(1.0f, n.z);
  float s = -1.0f / (sign + n.z);
  float t = n.x * n.y * s;
  a = {1.0f + sign * n.x * n.x * s, sign * t, -sign * n.x};
  b = {t, sign + n.y * n.y * s, -n.y};
}

// Roots of q22 x² − 2 q02 x + q00 = 0 (tangent lines of the dual conic) as a pixel range whose
// centres (i + 0.5) lie between them, clipped to [0, size).
inline bool pixel_range(double q00, double q02, double q22, int size, int& lo, int& hi) {
  double disc = std::max(0.0, q02 * q02 - q00 * q22);
  double s = std::sqrt(disc);
  double x_a = (q02 + s) / q22, x_b = (q02 - s) / q22;
  double x_min = std::min(x_a, x_b), x_max = std::max(x_a, x_b);
  double first = std::ceil(x_min - 0.5), last = std::floor(x_max - 0.5);
  if (!(first <= last) || last < 0 || first > size - 1) return false;
  lo = static_cast<int>(std::max(first, 0.0));
  hi = static_cast<int>(std::min(last, double(size - 1)));
  return true;
}

inline void not_drawn(SplatRaster& s) {
  s.x0 = 1;
  s.x1 = 0;
  s.y0 = s.y1 = 0;
}

inline void set_linear(float f[3], const Vec3f& w, const FrameConstants& k, int x0, int y0) {
  f[0] = dot(w, k.dx);
  f[1] = dot(w, k.dy);
  f[2] = dot(w, k.d0 + k.dx * float(x0) + k.dy * float(y0));
}

}  // namespace

std::size_t setup_splats(const DrawList& draws, const Projection& projection,
                         const SetupOptions& options, std::size_t begin, std::size_t end,
                         SplatRaster* out) {
  const FrameConstants k = frame_constants(projection);
  std::size_t drawn = 0;
  for (std::size_t i = begin; i < end; ++i) {
    SplatRaster& s = out[i - begin];
    const Vec3f c = draws.positions[i] - k.eye;
    const Vec3f n = draws.normals[i];
    const float r = draws.radii[i];
    const float nc = dot(n, c);
    const Vec3f a{dot(k.m0, n), dot(k.m1, n), dot(k.m2, n)};
    const Vec3f b{dot(k.m0, c), dot(k.m1, c), dot(k.m2, c)};
    const float half_depth = r * std::sqrt(std::max(0.0f, 1.0f - a.z * a.z));
    if (b.z - half_depth <= k.near || (options.cull_backfaces && nc > 0)) {
      not_drawn(s);
      continue;
    }
    const double r2 = double(r) * r;
    const double q22 = r2 * (1.0 - double(a.z) * a.z) - double(b.z) * b.z;
    const double q00 = r2 * (k.g00 - double(a.x) * a.x) - double(b.x) * b.x;
    const double q02 = r2 * (k.g02 - double(a.x) * a.z) - double(b.x) * b.z;
    const double q11 = r2 * (k.g11 - double(a.y) * a.y) - double(b.y) * b.y;
    const double q12 = r2 * (k.g12 - double(a.y) * a.z) - double(b.y) * b.z;
    int x0, x1, y0, y1;
    if (!pixel_range(q00, q02, q22, k.width, x0, x1) ||
        !pixel_range(q11, q12, q22, k.height, y0, y1)) {
      not_drawn(s);
      continue;
    }
    Vec3f ax, ay;
    disc_axes(n, ax, ay);
    const float inv_r = 1.0f / r;
    const Vec3f wu = (ax * nc - n * dot(ax, c)) * inv_r;
    const Vec3f wv = (ay * nc - n * dot(ay, c)) * inv_r;
    set_linear(s.l, n, k, x0, y0);
    set_linear(s.u, wu, k, x0, y0);
    set_linear(s.v, wv, k, x0, y0);
    s.nc = nc;
    s.zmin = b.z - half_depth;
    s.zmax = b.z + half_depth;
    s.x0 = static_cast<int16_t>(x0);
    s.x1 = static_cast<int16_t>(x1);
    s.y0 = static_cast<int16_t>(y0);
    s.y1 = static_cast<int16_t>(y1);
    ++drawn;
  }
  return drawn;
}

}  // namespace splatkit::render
