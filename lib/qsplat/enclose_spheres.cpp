#include "qsplat/enclose_spheres.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace splatkit::qsplat {

namespace {

struct D3 {
  double x, y, z;
};

D3 d3(const Vec3f& v) { return {v.x, v.y, v.z}; }

double dist(const D3& a, const D3& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

// The float sphere at (rounded) centre c that encloses every s[i], radius rounded up.
Sphere around(const D3& c, const Sphere* s, int count) {
  const Vec3f cf{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
  const D3 cd = d3(cf);
  double r = 0;
  for (int i = 0; i < count; ++i) r = std::max(r, dist(cd, d3(s[i].centre)) + s[i].radius);
  float rf = static_cast<float>(r);
  if (static_cast<double>(rf) < r) rf = std::nextafter(rf, std::numeric_limits<float>::infinity());
  return {cf, rf};
}

}  // namespace

Sphere enclose_spheres(const Sphere* s, int count, bool centroid_rule) {
  const auto centroid = [&] {
    D3 mean{0, 0, 0};
    for (int i = 0; i < count; ++i) {
      mean.x += s[i].centre.x;
      mean.y += s[i].centre.y;
      mean.z += s[i].centre.z;
    }
    return D3{mean.x / count, mean.y / count, mean.z / count};
  };
  if (centroid_rule || count == 1) return around(centroid(), s, count);
  // The pair whose spheres reach farthest apart: when the smallest sphere around it holds the
  // others, no sphere around them all is smaller (the usual case for a node's few neighbouring
  // splats), and it is the answer without the other candidates (whose ties it now wins).
  int pi = 0, pj = 1;
  double widest = -1;
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j) {
      const double w = dist(d3(s[i].centre), d3(s[j].centre)) + s[i].radius + s[j].radius;
      if (w > widest) {
        widest = w;
        pi = i;
        pj = j;
      }
    }
  const D3 a = d3(s[pi].centre), b = d3(s[pj].centre);
  const double d = dist(a, b), ra = s[pi].radius, rb = s[pj].radius;
  D3 centre;
  double least;  // the radius of the smallest sphere around the pair
  if (d + rb <= ra) {
    centre = a;
    least = ra;
  } else if (d + ra <= rb) {
    centre = b;
    least = rb;
  } else {
    // The pair's sphere spans from a's far side to b's far side along the line a -> b.
    least = (d + ra + rb) / 2;
    const double t = (least - ra) / d;
    centre = {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
  }
  Sphere best = around(centre, s, count);
  // Within float rounding of the pair's own sphere: minimal.
  if (best.radius <= least * (1 + 1e-6)) return best;
  auto consider = [&](const D3& c) {
    const Sphere t = around(c, s, count);
    if (t.radius < best.radius) best = t;
  };
  consider(centroid());
  D3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (int i = 0; i < count; ++i) {
    const D3 c = d3(s[i].centre);
    const double r = s[i].radius;
    lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
    hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
  }
  consider({(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2});
  return best;
}

}  // namespace splatkit::qsplat
