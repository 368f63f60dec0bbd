// The sphere the camera frames a model by (orbit views, the default view, turntables): centred on
// the middle of the bounding box of the splat centres, with the radius that reaches the farthest
// disc edge, max_i |c_i − centre| + r_i, and the box of the discs' reach (c_i ± r_i per axis),
// which the default views fill the frame with. The plain render, the QSplat render and the Sequential
// Point Tree render of one cloud use this one rule over the same splats (the leaves of a
// hierarchy), so that one --view shows the model in the same place whichever file is drawn.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "render/camera.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::render {

// `splat(i, centre, radius)` for i in [0, count): returns whether item i is a splat and, when it
// is, sets its centre and radius (scene units); called from several threads at once. Items that
// are not splats (a hierarchy's interior nodes) are skipped. No splat at all: centre 0, radius 0.
// Fixed chunks in parallel, combined in order, each minimum and maximum keeping the first of
// equal values: the result of one pass in item order, bit for bit, for any thread count.
template <class Splat>
BoundingSphere splat_bounds(std::size_t count, Splat&& splat) {
  constexpr float kInf = 3.4e38f;
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  const auto lower = [](Vec3f& lo, const Vec3f& v) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
  };
  const auto upper = [](Vec3f& hi, const Vec3f& v) {
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  };
  struct Part {
    Vec3f lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    float radius = 0;
    bool any = false;
  };
  std::vector<Part> parts(chunk_count(count, kChunk));
  for_each_chunk(count, kChunk, [&](std::size_t k, std::size_t b, std::size_t e) {
    Part& p = parts[k];
    Vec3f c{0, 0, 0};
    float r = 0;
    for (std::size_t i = b; i < e; ++i)
      if (splat(i, c, r)) {
        lower(p.lo, c);
        upper(p.hi, c);
        p.any = true;
      }
  });
  Part all;
  for (const Part& p : parts) {
    lower(all.lo, p.lo);
    upper(all.hi, p.hi);
    all.any = all.any || p.any;
  }
  BoundingSphere b;
  if (!all.any) return b;
  b.center = (all.lo + all.hi) * 0.5f;
  for (Part& p : parts) p = Part{};
  for_each_chunk(count, kChunk, [&](std::size_t k, std::size_t s, std::size_t e) {
    Part& p = parts[k];
    Vec3f c{0, 0, 0};
    float r = 0;
    for (std::size_t i = s; i < e; ++i)
      if (splat(i, c, r)) {
        p.radius = std::max(p.radius, norm(c - b.center) + r);
        lower(p.lo, c - Vec3f{r, r, r});
        upper(p.hi, c + Vec3f{r, r, r});
      }
  });
  b.box_lo = {kInf, kInf, kInf};
  b.box_hi = {-kInf, -kInf, -kInf};
  for (const Part& p : parts) {
    b.radius = std::max(b.radius, p.radius);
    lower(b.box_lo, p.lo);
    upper(b.box_hi, p.hi);
  }
  return b;
}

}  // namespace splatkit::render
