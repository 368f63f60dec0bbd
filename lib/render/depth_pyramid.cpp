#include "render/depth_pyramid.h"

#include <algorithm>
#include <limits>

namespace splatkit::render {

namespace {

uint32_t inf_bits() {
  const float inf = std::numeric_limits<float>::infinity();
  uint32_t b;
  std::memcpy(&b, &inf, 4);
  return b;
}

}  // namespace

void DepthPyramid::reset(int width, int height) {
  if (width != width_ || height != height_ || levels_.empty()) {
    width_ = width;
    height_ = height;
    levels_.clear();
    w_.clear();
    h_.clear();
    int w = width, h = height;
    while (true) {
      w_.push_back(w);
      h_.push_back(h);
      levels_.emplace_back(std::size_t(w) * h);
      if (w == 1 && h == 1) break;
      w = (w + 1) / 2;
      h = (h + 1) / 2;
    }
  }
  for (auto& l : levels_) std::fill(l.begin(), l.end(), inf_bits());
}

void DepthPyramid::update(PixelRect r) {
  r.x0 = std::max(r.x0, 0);
  r.y0 = std::max(r.y0, 0);
  r.x1 = std::min(r.x1, width_ - 1);
  r.y1 = std::min(r.y1, height_ - 1);
  if (r.empty()) return;
  for (std::size_t k = 1; k < levels_.size(); ++k) {
    r = {r.x0 >> 1, r.y0 >> 1, r.x1 >> 1, r.y1 >> 1};
    const int pw = w_[k - 1], ph = h_[k - 1], w = w_[k];
    const uint32_t* below = levels_[k - 1].data();
    uint32_t* here = levels_[k].data();
    for (int y = r.y0; y <= r.y1; ++y) {
      const int by0 = 2 * y, by1 = std::min(2 * y + 1, ph - 1);
      for (int x = r.x0; x <= r.x1; ++x) {
        const int bx0 = 2 * x, bx1 = std::min(2 * x + 1, pw - 1);
        // Non-negative float bits order like the floats.
        here[std::size_t(y) * w + x] = std::max(
            std::max(below[std::size_t(by0) * pw + bx0], below[std::size_t(by0) * pw + bx1]),
            std::max(below[std::size_t(by1) * pw + bx0], below[std::size_t(by1) * pw + bx1]));
      }
    }
  }
}

float DepthPyramid::max_depth(PixelRect r) const {
  r.x0 = std::max(r.x0, 0);
  r.y0 = std::max(r.y0, 0);
  r.x1 = std::min(r.x1, width_ - 1);
  r.y1 = std::min(r.y1, height_ - 1);
  std::size_t k = 0;
  while (k + 1 < levels_.size() && ((r.x1 >> k) - (r.x0 >> k) > 3 || (r.y1 >> k) - (r.y0 >> k) > 3))
    ++k;
  const int x0 = r.x0 >> k, x1 = r.x1 >> k, y0 = r.y0 >> k, y1 = r.y1 >> k, w = w_[k];
  uint32_t m = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) m = std::max(m, levels_[k][std::size_t(y) * w + x]);
  return as_float(m);
}

}  // namespace splatkit::render
