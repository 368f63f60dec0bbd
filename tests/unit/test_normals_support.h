// Small helpers shared by the test_normals_*.cpp files: a platform-independent RNG and tiny
// synthetic clouds with analytic normals.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "splatkit/deterministic_rng.h"
#include "splatkit/splat_cloud.h"

namespace splatkit::normals_test {

using Rng = DeterministicRng;

// A jittered nx × ny grid of spacing h on the plane z = z0.
inline SplatCloud jittered_plane(int nx, int ny, float h, float z0, uint64_t seed) {
  Rng rng{seed};
  SplatCloud c;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      c.positions.push_back({(static_cast<float>(i) + 0.3f * (rng.uniformf() - 0.5f)) * h,
                             (static_cast<float>(j) + 0.3f * (rng.uniformf() - 0.5f)) * h, z0});
  return c;
}

// n points uniform on the sphere of radius r centred at `centre`.
inline SplatCloud random_sphere(std::size_t n, float r, Vec3f centre, uint64_t seed) {
  Rng rng{seed};
  SplatCloud c;
  while (c.positions.size() < n) {
    Vec3f v{2 * rng.uniformf() - 1, 2 * rng.uniformf() - 1, 2 * rng.uniformf() - 1};
    float len = norm(v);
    if (len < 0.1f || len > 1.0f) continue;
    c.positions.push_back(centre + v * (r / len));
  }
  return c;
}

inline bool all_finite(const SplatCloud& c) {
  for (const Vec3f& n : c.normals)
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return false;
  for (float r : c.radii)
    if (!std::isfinite(r)) return false;
  return true;
}

inline bool all_unit(const SplatCloud& c) {
  for (const Vec3f& n : c.normals)
    if (std::fabs(norm(n) - 1.0f) > 1e-5f) return false;
  return true;
}

}  // namespace splatkit::normals_test
