// DepthPyramid: max_depth over any rectangle is at least every level-0 value inside it and never
// more than the largest level-0 value of the coarse cells it reads; update() keeps it so after
// writes, against brute force on random images and rectangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "render/depth_pyramid.h"

namespace splatkit::render {
namespace {

TEST(DepthPyramid, MaxDepthBoundsEveryPixel) {
  std::mt19937 rng(3);
  for (auto [w, h] : {std::pair{37, 23}, std::pair{64, 64}, std::pair{1, 9}, std::pair{130, 5}}) {
    DepthPyramid p;
    p.reset(w, h);
    std::uniform_int_distribution<int> X(0, w - 1), Y(0, h - 1);
    std::uniform_real_distribution<float> D(0.5f, 100.0f);
    EXPECT_EQ(p.max_depth({0, 0, w - 1, h - 1}), std::numeric_limits<float>::infinity());
    // Fill everything (random depths) in a few rectangles at a time.
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) p.lower(x, y, D(rng));
    p.update({0, 0, w - 1, h - 1});
    for (int round = 0; round < 200; ++round) {
      int x = X(rng), y = Y(rng);
      p.lower(x, y, D(rng) * 0.1f);
      p.update({x, y, x, y});
      int x0 = X(rng), x1 = X(rng), y0 = Y(rng), y1 = Y(rng);
      if (x0 > x1) std::swap(x0, x1);
      if (y0 > y1) std::swap(y0, y1);
      float brute = 0;
      for (int yy = y0; yy <= y1; ++yy)
        for (int xx = x0; xx <= x1; ++xx) brute = std::max(brute, p.pixel(xx, yy));
      const float got = p.max_depth({x0, y0, x1, y1});
      EXPECT_GE(got, brute);
      float whole = 0;
      for (int yy = 0; yy < h; ++yy)
        for (int xx = 0; xx < w; ++xx) whole = std::max(whole, p.pixel(xx, yy));
      EXPECT_LE(got, whole);
    }
  }
}

TEST(DepthPyramid, LowerOnlyLowers) {
  DepthPyramid p;
  p.reset(4, 4);
  p.lower(1, 2, 5);
  p.lower(1, 2, 7);
  EXPECT_EQ(p.pixel(1, 2), 5);
  p.lower(1, 2, 2);
  EXPECT_EQ(p.pixel(1, 2), 2);
  // A run lowers its pixels, where that is less, and no other.
  p.lower_run(0, 2, 2, 3);
  EXPECT_EQ(p.pixel(0, 2), 3);
  EXPECT_EQ(p.pixel(1, 2), 2);
  EXPECT_EQ(p.pixel(2, 2), 3);
  EXPECT_EQ(p.pixel(3, 2), std::numeric_limits<float>::infinity());
  EXPECT_EQ(p.pixel(0, 1), std::numeric_limits<float>::infinity());
  EXPECT_EQ(p.pixel(0, 3), std::numeric_limits<float>::infinity());
}

}  // namespace
}  // namespace splatkit::render
