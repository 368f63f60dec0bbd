// A max-depth pyramid of the front surface (hierarchical Z-buffer, Greene, Kass and Miller 1993)
// for conservative occlusion queries on the CPU. Level 0 holds, per pixel, an upper bound of the
// depth of the nearest fragment drawn so far (+inf where nothing is drawn); a cell of level k is
// the maximum of its (up to) four cells of level k − 1. Depths are camera-space z (camera.h).
//
// Writers lower level-0 pixels with lower() (safe from several threads at once: an atomic
// minimum on the float's bits, which order like the numbers for non-negative floats), then call
// update() over the pixels they touched; max_depth() reads whatever level covers a rectangle in
// at most 4 × 4 cells.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <vector>

namespace splatkit::render {

struct PixelRect {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive; empty when x0 > x1 or y0 > y1
  bool empty() const { return x0 > x1 || y0 > y1; }
  void extend(const PixelRect& r) {
    if (r.empty()) return;
    if (empty()) {
      *this = r;
      return;
    }
    x0 = x0 < r.x0 ? x0 : r.x0;
    y0 = y0 < r.y0 ? y0 : r.y0;
    x1 = x1 > r.x1 ? x1 : r.x1;
    y1 = y1 > r.y1 ? y1 : r.y1;
  }
};

class DepthPyramid {
 public:
  // Sizes the pyramid for a width × height image and clears every level to +inf.
  void reset(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }

  // Lowers pixel (x, y) of level 0 to `depth` (>= 0) if that is less.
  void lower(int x, int y, float depth) {
    uint32_t bits;
    std::memcpy(&bits, &depth, 4);
    std::atomic_ref<uint32_t> cell(levels_[0][std::size_t(y) * width_ + x]);
    uint32_t old = cell.load(std::memory_order_relaxed);
    while (bits < old && !cell.compare_exchange_weak(old, bits, std::memory_order_relaxed)) {
    }
  }
  // Lowers pixels x0..x1 of row y of level 0 to `depth` where that is less.
  void lower_run(int x0, int x1, int y, float depth) {
    uint32_t bits;
    std::memcpy(&bits, &depth, 4);
    uint32_t* row = levels_[0].data() + std::size_t(y) * width_;
    for (int x = x0; x <= x1; ++x) {
      std::atomic_ref<uint32_t> cell(row[x]);
      uint32_t old = cell.load(std::memory_order_relaxed);
      while (bits < old && !cell.compare_exchange_weak(old, bits, std::memory_order_relaxed)) {
      }
    }
  }
  // Recomputes the upper levels over the level-0 pixels of `r` (clipped to the image).
  void update(PixelRect r);
  // The largest depth over the pixels of `r` (clipped to the image; must not be empty after
  // clipping), read from the coarsest useful level: an upper bound of every level-0 value there.
  float max_depth(PixelRect r) const;
  float pixel(int x, int y) const { return as_float(levels_[0][std::size_t(y) * width_ + x]); }

 private:
  static float as_float(uint32_t b) {
    float f;
    std::memcpy(&f, &b, 4);
    return f;
  }
  int width_ = 0, height_ = 0;
  std::vector<std::vector<uint32_t>> levels_;  // float bits
  std::vector<int> w_, h_;                     // per level
};

}  // namespace splatkit::render
