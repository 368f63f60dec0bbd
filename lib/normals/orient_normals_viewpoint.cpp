#include "normals/orient_normals_viewpoint.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <functional>

namespace splatkit {

namespace {

// Flips normals[i] where towards(i) < 0; returns how many.
template <class Towards>
std::size_t flip_where_away(std::span<Vec3f> normals, Towards&& towards) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, normals.size(), 4096), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t flipped) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
          if (towards(i) < 0) {
            normals[i] = -normals[i];
            ++flipped;
          }
        return flipped;
      },
      std::plus<>());
}

// n·(v − p) in double: a viewpoint far from the cloud must not lose the offset to rounding.
double towards_point(const Vec3f& p, const Vec3f& n, const std::array<double, 3>& v) {
  return n.x * (v[0] - p.x) + n.y * (v[1] - p.y) + n.z * (v[2] - p.z);
}

}  // namespace

std::size_t orient_normals_sensors(std::span<const Vec3f> positions, std::span<Vec3f> normals,
                                   std::span<const std::array<double, 3>> sensors) {
  return flip_where_away(
      normals, [&](std::size_t i) { return towards_point(positions[i], normals[i], sensors[i]); });
}

std::size_t orient_normals_up(std::span<Vec3f> normals, const Vec3f& up) {
  return flip_where_away(normals, [&](std::size_t i) { return dot(normals[i], up); });
}

std::size_t orient_normals_viewpoint(std::span<const Vec3f> positions, std::span<Vec3f> normals,
                                     const std::array<double, 3>& viewpoint) {
  return flip_where_away(
      normals, [&](std::size_t i) { return towards_point(positions[i], normals[i], viewpoint); });
}

}  // namespace splatkit
