// Double-precision 3-vector for the offline geometry of the splat graph (plane lines, chords,
// classification), where float cancellation would decide signs wrongly; the stored data stays
// float (splatkit::Vec3f) and converts on entry with to_vec3d.
#pragma once

#include <cmath>

#include "splatkit/vec3.h"

namespace splatkit::graph {

struct Vec3d {
  double x = 0, y = 0, z = 0;

  constexpr Vec3d operator+(const Vec3d& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3d operator-(const Vec3d& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3d operator-() const { return {-x, -y, -z}; }
  constexpr Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3d operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3d& operator+=(const Vec3d& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr bool operator==(const Vec3d&) const = default;
};

constexpr Vec3d to_vec3d(const Vec3f& v) { return {v.x, v.y, v.z}; }
constexpr double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3d& a) { return std::sqrt(dot(a, a)); }

}  // namespace splatkit::graph
