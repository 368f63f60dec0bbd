// Nearest-splat rendering without blending (`--blend zbuffer`): the fast path for splats of a few
// pixels, the way QSplat [Rusinkiewicz00] and Sequential Point Trees [Dachsbacher03] draw them
// (docs/references.md). Each splat covers, as a screen-aligned disc of its projected radius
// r·focal/z, the pixels whose centres lie inside that disc (or, when none does, the pixel under
// its projected centre, so that a splat never vanishes); each pixel keeps the splat of least
// (depth of the splat's centre, splat index). No A-buffer, no blending, no clipping: silhouettes
// and the seams between splats are not smoothed, and an ellipse is drawn as its enclosing circle.
//
// Pixels hold one 64-bit key, (depth bits << 32) | index, updated by an atomic minimum: the
// result does not depend on the order in which threads draw, so images are byte-identical for any
// thread count.
#pragma once

#include <algorithm>
#include <atomic>
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
  // Pixel centres (i + 0.5, j + 0.5) within rp of (px, py): the box first, in coordinates
  // clamped to a little beyond the image so that the integer conversions below are exact
  // floors (the x86-64 baseline has no rounding instruction: std::floor is a call).
  const float w = static_cast<float>(b.width), h = static_cast<float>(b.height);
  auto clamp = [](float v, float hi) { return v < -2.0f ? -2.0f : (v > hi ? hi : v); };
  auto floor_in = [&](float v, float hi) {
    v = clamp(v, hi);
    const int i = static_cast<int>(v);
    return i - (static_cast<float>(i) > v);
  };
  auto ceil_in = [&](float v, float hi) {
    v = clamp(v, hi);
    const int i = static_cast<int>(v);
    return i + (static_cast<float>(i) < v);
  };
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

}  // namespace splatkit::render
