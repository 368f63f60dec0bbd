// A minimal 3-vector of floats (12 bytes, no alignment padding) for the hot loops; Eigen is used
// where linear algebra is needed (eigen-solvers, small systems).
#pragma once

#include <cmath>

namespace splatkit {

struct Vec3f {
  float x = 0, y = 0, z = 0;

  constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3f operator+(const Vec3f& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3f operator-(const Vec3f& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3f operator-() const { return {-x, -y, -z}; }
  constexpr Vec3f operator*(float s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3f operator/(float s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3f& operator+=(const Vec3f& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3f& operator-=(const Vec3f& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3f& operator*=(float s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr bool operator==(const Vec3f&) const = default;
};

constexpr float dot(const Vec3f& a, const Vec3f& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(const Vec3f& a, const Vec3f& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr float squared_norm(const Vec3f& a) { return dot(a, a); }
inline float norm(const Vec3f& a) { return std::sqrt(dot(a, a)); }
inline Vec3f normalized(const Vec3f& a) {
  float n = norm(a);
  return n > 0 ? a / n : Vec3f{0, 0, 0};
}
constexpr float squared_distance(const Vec3f& a, const Vec3f& b) { return squared_norm(a - b); }

}  // namespace splatkit
