#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "splatkit/error.h"

namespace splatkit::render {

namespace {

constexpr float kDegToRad = std::numbers::pi_v<float> / 180.0f;

// The orbit's frame about unit `w`: a at azimuth 0 (+x made perpendicular to w, or +y when w is
// close to x), b = w × a at azimuth 90°.
struct OrbitAxes {
  Vec3f a, b;
};

OrbitAxes orbit_axes(const Vec3f& w) {
  const Vec3f ref = std::fabs(w.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
  const Vec3f a = normalized(ref - w * dot(ref, w));
  return {a, cross(w, a)};
}

// Rodrigues' rotation of v by angle (cos cs, sin sn) about unit axis k.
Vec3f rotated(const Vec3f& v, const Vec3f& k, float cs, float sn) {
  return v * cs + cross(k, v) * sn + k * (dot(k, v) * (1 - cs));
}

}  // namespace

bool up_orients_view(const Vec3f& view, const Vec3f& up) {
  return norm(cross(normalized(view), up)) > 1e-6f * norm(up);
}

Vec3f automatic_up(const Vec3f& view, const Vec3f& up) {
  const Vec3f w = normalized(up);
  if (!(std::fabs(dot(normalized(view), w)) > kAutoUpCos)) return up;
  return orbit_axes(w).b;
}

Camera turned_camera(const Camera& camera, const Vec3f& axis, float angle_rad) {
  const Vec3f k = normalized(axis);
  const float cs = std::cos(angle_rad), sn = std::sin(angle_rad);
  Camera out = camera;
  out.eye = camera.target + rotated(camera.eye - camera.target, k, cs, sn);
  if (norm(cross(k, normalized(camera.up))) > 1e-6f) out.up = rotated(camera.up, k, cs, sn);
  return out;
}

Projection make_projection(const Camera& camera) {
  if (camera.width <= 0 || camera.height <= 0)
    throw_usage("image size must be positive, got " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height));
  if (!(camera.fov_y_deg > 0 && camera.fov_y_deg < 180))
    throw_usage("--fov must be in (0, 180) degrees");
  Vec3f view = camera.target - camera.eye;
  float distance = norm(view);
  if (!(distance > 0) || !std::isfinite(distance))
    throw_usage("camera eye and target must be distinct finite points");
  Projection p;
  p.eye = camera.eye;
  p.forward = view / distance;
  if (!up_orients_view(p.forward, camera.up))
    throw_usage("camera up vector is parallel to the viewing direction");
  p.right = normalized(cross(p.forward, camera.up));
  p.down = cross(p.forward, p.right);
  p.width = camera.width;
  p.height = camera.height;
  p.focal_px = 0.5f * camera.height / std::tan(0.5f * camera.fov_y_deg * kDegToRad);
  p.cx = 0.5f * camera.width;
  p.cy = 0.5f * camera.height;
  p.near = 1e-4f * distance;
  return p;
}

float framing_distance(const BoundingSphere& sphere, float fov_y_deg, int width, int height) {
  float half_y = 0.5f * fov_y_deg * kDegToRad;
  float half_x = std::atan(std::tan(half_y) * width / std::max(height, 1));
  float half = std::min(half_x, half_y);
  constexpr float kMargin = 1.08f;
  return kMargin * std::max(sphere.radius, 1e-6f) / std::sin(half);
}

float box_framing_distance(const BoundingSphere& sphere, const Vec3f& dir, const Vec3f& up,
                           float fov_y_deg, int width, int height) {
  const float loose = framing_distance(sphere, fov_y_deg, width, height);
  if (!sphere.has_box()) return loose;
  constexpr float kMargin = 1.08f;
  const float tan_y = std::tan(0.5f * fov_y_deg * kDegToRad);
  const float tan_x = tan_y * static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const Vec3f forward = -normalized(dir);
  const Vec3f right = normalized(cross(forward, automatic_up(forward, up)));
  const Vec3f down = cross(forward, right);
  // Corner o (from the centre) at depth d + o.forward: inside when |o.right| <= tan_x (d +
  // o.forward) / margin, and likewise down; in front of the eye by at least a tenth of the
  // radius.
  float d = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3f corner{(k & 1) ? sphere.box_hi.x : sphere.box_lo.x,
                       (k & 2) ? sphere.box_hi.y : sphere.box_lo.y,
                       (k & 4) ? sphere.box_hi.z : sphere.box_lo.z};
    const Vec3f o = corner - sphere.center;
    const float z = dot(o, forward);
    d = std::max({d, kMargin * std::fabs(dot(o, right)) / tan_x - z,
                  kMargin * std::fabs(dot(o, down)) / tan_y - z, 0.1f * sphere.radius - z});
  }
  return std::isfinite(d) && d > 0 ? std::min(d, loose) : loose;
}

Camera orbit_camera(const BoundingSphere& sphere, float azimuth_deg, float elevation_deg,
                    std::optional<float> distance, const Vec3f& up, float fov_y_deg, int width,
                    int height) {
  Vec3f w = normalized(up);
  if (!(norm(w) > 0)) throw_usage("--up must be a non-zero vector");
  const auto [a, b] = orbit_axes(w);
  float az = azimuth_deg * kDegToRad, el = elevation_deg * kDegToRad;
  Vec3f dir =
      a * (std::cos(el) * std::cos(az)) + b * (std::cos(el) * std::sin(az)) + w * std::sin(el);
  float d = distance ? *distance
                     : box_framing_distance(sphere, dir, w, fov_y_deg, width, height);
  if (!(d > 0) || !std::isfinite(d)) throw_usage("--view distance must be positive");
  Camera c;
  c.target = sphere.center;
  c.eye = sphere.center + dir * d;
  c.up = automatic_up(c.target - c.eye, w);
  c.fov_y_deg = fov_y_deg;
  c.width = width;
  c.height = height;
  return c;
}

}  // namespace splatkit::render
