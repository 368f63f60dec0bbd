// Nearest-splat rendering without blending (`--blend zbuffer`): the fast path for splats of a few
// pixels, the way QSplat [Rusinkiewicz00] and Sequential Point Trees [Dachsbacher03] draw them
// (docs/references.md). A splat with a normal (zbuffer_disc) covers the pixels whose rays hit its
// disc, the perspective-correct ellipse the blended render draws (setup_splats.h), so that
// silhouettes are those of the plain render; zbuffer_splat draws a screen-aligned disc of the
// projected radius r·focal/z instead (a point, or a splat of a pixel or less, where the two cover
// the same pixel centres or nearly). Either way a splat that covers no pixel centre covers the
// pixel under its projected centre, so that it never vanishes; each pixel keeps the splat of
// least (depth of the splat's centre, splat index). No A-buffer, no blending, no clipping:
// silhouettes and the seams between splats are not smoothed, and an elliptic splat is drawn as
// the circle of its larger semi-axis.
//
// Pixels hold one 64-bit key, (depth bits << 32) | index, updated by an atomic minimum: the
// result does not depend on the order in which threads draw, so images are byte-identical for any
// thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "render/camera.h"

namespace splatkit::render {

inline constexpr uint64_t kNoSplatKey = ~uint64_t{0};

struct DepthKeyBuffer {
  int width = 0, height = 0;
  std::vector<uint64_t> keys;  // #H×W, kNoSplatKey where nothing is drawn

  // Sizes the buffer and clears it (in parallel).
  void reset(int w, int h);
  static uint32_t index_of(uint64_t key) { return static_cast<uint32_t>(key); }
  static float depth_of(uint64_t key) {
    const auto bits = static_cast<uint32_t>(key >> 32);
    float z;
    std::memcpy(&z, &bits, 4);
    return z;
  }
};

// Floor and ceiling of v clamped to [-2, hi]: pixel bounds a little beyond the image, where the
// integer conversions are exact (the x86-64 baseline has no rounding instruction: std::floor is
// a call).
inline int floor_in(float v, float hi) {
  v = v < -2.0f ? -2.0f : (v > hi ? hi : v);
  const int i = static_cast<int>(v);
  return i - (static_cast<float>(i) > v);
}
inline int ceil_in(float v, float hi) {
  v = v < -2.0f ? -2.0f : (v > hi ? hi : v);
  const int i = static_cast<int>(v);
  return i + (static_cast<float>(i) < v);
}

// Writes the key of splat `index` at depth z (> 0) into the pixel under (px, py), if that pixel
// is in the image: a splat drawn as a point. Safe to call from several threads at once.
inline bool zbuffer_point(DepthKeyBuffer& b, float px, float py, float z, uint32_t index) {
  if (!(px >= 0.0f && py >= 0.0f && px < static_cast<float>(b.width) &&
        py < static_cast<float>(b.height)))
    return false;
  const std::size_t at =
      static_cast<std::size_t>(static_cast<int>(py)) * static_cast<std::size_t>(b.width) +
      static_cast<std::size_t>(static_cast<int>(px));
  uint32_t bits;
  std::memcpy(&bits, &z, 4);  // positive floats order like their bit patterns
  const uint64_t key = (uint64_t{bits} << 32) | index;
  std::atomic_ref<uint64_t> slot(b.keys[at]);
  uint64_t cur = slot.load(std::memory_order_relaxed);
  while (key < cur && !slot.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
  }
  return true;
}

// Draws splat `index` with camera-space centre `c` (Projection::to_camera) and radius `r` (scene
// units). Not drawn (returns false) when any part of it is nearer than projection.near or when it
// covers no pixel of the image. Safe to call from several threads at once.
inline bool zbuffer_splat(DepthKeyBuffer& b, const Projection& p, const Vec3f& c, float r,
                          uint32_t index) {
  if (!(c.z - r >= p.near)) return false;
  const float inv = 1.0f / c.z;
  const float px = p.cx + p.focal_px * c.x * inv, py = p.cy + p.focal_px * c.y * inv;
  const float rp = p.focal_px * r * inv;
  // Pixel centres (i + 0.5, j + 0.5) within rp of (px, py): the box first.
  const float w = static_cast<float>(b.width), h = static_cast<float>(b.height);
  int x0 = ceil_in(px - rp - 0.5f, w + 2.0f), x1 = floor_in(px + rp - 0.5f, w + 2.0f);
  int y0 = ceil_in(py - rp - 0.5f, h + 2.0f), y1 = floor_in(py + rp - 0.5f, h + 2.0f);
  if (x0 > x1 || y0 > y1) {  // no pixel centre in the box: the pixel under the centre
    x0 = x1 = floor_in(px, w + 2.0f);
    y0 = y1 = floor_in(py, h + 2.0f);
  }
  if (x1 < 0 || y1 < 0 || x0 >= b.width || y0 >= b.height) return false;
  x0 = x0 < 0 ? 0 : x0;
  y0 = y0 < 0 ? 0 : y0;
  x1 = x1 >= b.width ? b.width - 1 : x1;
  y1 = y1 >= b.height ? b.height - 1 : y1;
  uint32_t bits;
  std::memcpy(&bits, &c.z, 4);  // positive floats order like their bit patterns
  const uint64_t key = (uint64_t{bits} << 32) | index;
  auto put = [&](std::size_t at) {
    std::atomic_ref<uint64_t> slot(b.keys[at]);
    uint64_t cur = slot.load(std::memory_order_relaxed);
    while (key < cur && !slot.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
    }
  };
  if (x0 == x1 && y0 == y1) {
    put(static_cast<std::size_t>(y0) * b.width + x0);
    return true;
  }
  const float r2 = rp * rp;
  bool any = false;
  // One branch per pixel, taken only where the splat is nearer: whether the pixel centre lies in
  // the disc is folded into it (an edge of the disc is as hard to predict as the depth test).
  for (int y = y0; y <= y1; ++y) {
    const float dy = static_cast<float>(y) + 0.5f - py;
    const float rest = r2 - dy * dy;
    uint64_t* row = b.keys.data() + static_cast<std::size_t>(y) * b.width;
    for (int x = x0; x <= x1; ++x) {
      const float dx = static_cast<float>(x) + 0.5f - px;
      const bool in = !(dx * dx > rest);
      any |= in;
      std::atomic_ref<uint64_t> slot(row[x]);
      uint64_t cur = slot.load(std::memory_order_relaxed);
      if (in & (key < cur))
        while (key < cur && !slot.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
        }
    }
  }
  return any;
}

// A direction in the scene frame in camera space (Projection::to_camera without the eye).
inline Vec3f camera_direction(const Projection& p, const Vec3f& v) {
  return {dot(v, p.right), dot(v, p.down), dot(v, p.forward)};
}

// Splats whose projected radius is at most this many pixels are drawn by zbuffer_disc as
// zbuffer_splat draws them: a disc of half a pixel covers at most the pixel centre nearest its
// own, whatever its orientation, so the ray test would buy nothing.
inline constexpr float kDiscMinRadiusPx = 0.5f;

// Draws splat `index`, the disc of camera-space centre `c`, camera-space unit normal
// `camera_normal()` (camera_direction; called only for discs of more than kDiscMinRadiusPx, so
// that small splats cost what zbuffer_splat costs) and radius `r`, as the pixels whose centre rays meet the disc in front of the
// eye (with the pixel ray d, L = n·d, U = (n·c)(a·d) − (a·c)L and V likewise with b, a and b unit
// axes of the disc's plane: inside iff U² + V² ≤ r²L² and (n·c)L > 0; setup_splats.h). A disc
// seen edge-on covers no pixel centre and draws the pixel under its projected centre. Not drawn
// (returns false) as zbuffer_splat. Safe to call from several threads at once.
template <class CameraNormal>
inline bool zbuffer_disc(DepthKeyBuffer& b, const Projection& p, const Vec3f& c,
                         CameraNormal&& camera_normal, float r, uint32_t index) {
  if (!(c.z - r >= p.near)) return false;
  const float f = p.focal_px;
  if (f * r <= kDiscMinRadiusPx * c.z) return zbuffer_splat(b, p, c, r, index);
  const Vec3f n = camera_normal();
  // Pixel box: the disc lies in its bounding sphere, whose points have depths in [z − r, z + r].
  const float to_near = f / (c.z - r), to_far = f / (c.z + r);
  auto reach = [&](float lo, float hi, float centre, float& from, float& to) {
    from = centre + lo * (lo >= 0 ? to_far : to_near);
    to = centre + hi * (hi >= 0 ? to_near : to_far);
  };
  float bx0, bx1, by0, by1;
  reach(c.x - r, c.x + r, p.cx, bx0, bx1);
  reach(c.y - r, c.y + r, p.cy, by0, by1);
  const float w = static_cast<float>(b.width), h = static_cast<float>(b.height);
  int x0 = std::max(0, ceil_in(bx0 - 0.5f, w + 2.0f));
  int x1 = std::min(b.width - 1, floor_in(bx1 - 0.5f, w + 2.0f));
  int y0 = std::max(0, ceil_in(by0 - 0.5f, h + 2.0f));
  int y1 = std::min(b.height - 1, floor_in(by1 - 0.5f, h + 2.0f));
  // Unit axes a, b of the disc's plane without a square root ([Duff17]); then L, U, V as linear functions of the pixel ray scaled by
  // the focal length, d = (x + 0.5 − cx, y + 0.5 − cy, f) (the test is the same for any positive
  // scale of d).
  const float sign = n.z >= 0 ? 1.0f : -1.0f;
  const float q = -1.0f / (sign + n.z), nxy = n.x * n.y * q;
  const Vec3f a{1.0f + sign * n.x * n.x * q, sign * nxy, -sign * n.x};
  const Vec3f bb{nxy, sign + n.y * n.y * q, -n.y};
  const float nc = dot(n, c);
  const Vec3f u = a * nc - n * dot(a, c), v = bb * nc - n * dot(bb, c);
  const float r2 = r * r;
  uint32_t bits;
  std::memcpy(&bits, &c.z, 4);  // positive floats order like their bit patterns
  const uint64_t key = (uint64_t{bits} << 32) | index;
  // Along a row, U² + V² − r²L² is a quadratic in x, αx² + βx + γ: positive α (every disc in
  // front of the eye but one seen exactly edge-on), its roots bound the row's pixels, which are
  // then tested one by one, from a hundredth of a pixel beyond them (so that the roots' rounding
  // decides nothing but pixel centres within float rounding of the edge).
  // Boxes a few pixels wide are tested whole: cheaper than the roots.
  const float alpha = u.x * u.x + v.x * v.x - r2 * n.x * n.x;
  const bool spans =
      x1 - x0 >= 4 && alpha > 1e-12f * (u.x * u.x + v.x * v.x + r2 * n.x * n.x);
  const float half_over_alpha = spans ? 0.5f / alpha : 0.0f;
  bool any = false;
  for (int y = y0; y <= y1; ++y) {
    const float dy = static_cast<float>(y) + 0.5f - p.cy;
    const float l_row = n.y * dy + n.z * f, u_row = u.y * dy + u.z * f, v_row = v.y * dy + v.z * f;
    uint64_t* row = b.keys.data() + static_cast<std::size_t>(y) * b.width;
    int from = x0, to = x1;
    if (spans) {
      const float beta = 2 * (u.x * u_row + v.x * v_row - r2 * n.x * l_row);
      const float gamma = u_row * u_row + v_row * v_row - r2 * l_row * l_row;
      const float disc = beta * beta - 4 * alpha * gamma;
      if (!(disc >= 0)) continue;  // the row misses the ellipse
      // dx = x + 0.5 − cx at the roots.
      const float root = std::sqrt(disc) * half_over_alpha;
      const float mid = p.cx - 0.5f - beta * half_over_alpha;
      from = std::max(from, ceil_in(mid - root - 0.01f, w + 2.0f));
      to = std::min(to, floor_in(mid + root + 0.01f, w + 2.0f));
    }
    for (int x = from; x <= to; ++x) {
      const float dx = static_cast<float>(x) + 0.5f - p.cx;
      const float l = n.x * dx + l_row, uu = u.x * dx + u_row, vv = v.x * dx + v_row;
      const bool in = uu * uu + vv * vv <= r2 * l * l && nc * l > 0;
      any |= in;
      std::atomic_ref<uint64_t> slot(row[x]);
      uint64_t cur = slot.load(std::memory_order_relaxed);
      if (in & (key < cur))
        while (key < cur && !slot.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
        }
    }
  }
  if (any) return true;
  const float inv = f / c.z;
  return zbuffer_point(b, p.cx + c.x * inv, p.cy + c.y * inv, c.z, index);
}

}  // namespace splatkit::render
