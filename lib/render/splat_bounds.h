// The sphere the camera frames a model by (orbit views, the default view, turntables): centred on
// the middle of the bounding box of the splat centres, with the radius that reaches the farthest
// disc edge, max_i |c_i − centre| + r_i, and the box of the discs' reach (c_i ± r_i per axis),
// which the default views fill the frame with. The plain render, the QSplat render and the Sequential
// Point Tree render of one cloud use this one rule over the same splats (the leaves of a
// hierarchy), so that one --view shows the model in the same place whichever file is drawn.
#pragma once

#include <algorithm>
#include <cstddef>

#include "render/camera.h"

namespace splatkit::render {

// `splat(i, centre, radius)` for i in [0, count): returns whether item i is a splat and, when it
// is, sets its centre and radius (scene units). Items that are not splats (a hierarchy's interior
// nodes) are skipped. No splat at all: centre 0, radius 0. The same result for any item order
// (minima and maxima only).
template <class Splat>
BoundingSphere splat_bounds(std::size_t count, Splat&& splat) {
  constexpr float kInf = 3.4e38f;
  Vec3f lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  Vec3f c{0, 0, 0};
  float r = 0;
  bool any = false;
  for (std::size_t i = 0; i < count; ++i)
    if (splat(i, c, r)) {
      lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
      hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
      any = true;
    }
  BoundingSphere b;
  if (!any) return b;
  b.center = (lo + hi) * 0.5f;
  b.box_lo = {kInf, kInf, kInf};
  b.box_hi = {-kInf, -kInf, -kInf};
  for (std::size_t i = 0; i < count; ++i)
    if (splat(i, c, r)) {
      b.radius = std::max(b.radius, norm(c - b.center) + r);
      b.box_lo = {std::min(b.box_lo.x, c.x - r), std::min(b.box_lo.y, c.y - r),
                  std::min(b.box_lo.z, c.z - r)};
      b.box_hi = {std::max(b.box_hi.x, c.x + r), std::max(b.box_hi.y, c.y + r),
                  std::max(b.box_hi.z, c.z + r)};
    }
  return b;
}

}  // namespace splatkit::render
