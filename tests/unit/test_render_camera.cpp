// The camera's up vector rule: automatic_up() keeps `up` except for top and bottom views, which
// become maps with +y up (+x right from above, left from below), the same for --eye cameras and
// orbit cameras at elevation ±90°; explicit parallel up vectors are refused; turned_camera()
// spins a top view in the image and keeps an up along the axis bit for bit; default views fill the
// frame with the splats' box.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "render/camera.h"
#include "splatkit/error.h"

namespace splatkit::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

Camera looking(const Vec3f& eye, const Vec3f& target, const Vec3f& up) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = up;
  c.width = 64;
  c.height = 48;
  return c;
}

// Pixel coordinates of scene point q.
std::array<float, 2> project(const Projection& p, const Vec3f& q) {
  const Vec3f c = p.to_camera(q);
  return {p.cx + p.focal_px * c.x / c.z, p.cy + p.focal_px * c.y / c.z};
}

void expect_near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
  EXPECT_NEAR(norm(a - b), 0, tol) << a.x << "," << a.y << "," << a.z;
}

TEST(RenderCamera, AutomaticUpKeepsUpOutsideTopAndBottomViews) {
  const Vec3f z{0, 0, 2};
  // Unchanged, not even normalised, at 1° and more from the axis.
  for (float deg : {1.0f, 25.0f, 90.0f, 179.0f}) {
    const float t = deg * kPi / 180;
    const Vec3f view{std::sin(t), 0, -std::cos(t)};
    EXPECT_EQ(automatic_up(view, z), z) << deg;
  }
  // Within 0.81° of ±up: +y.
  for (float deg : {0.0f, 0.5f, 179.5f, 180.0f}) {
    const float t = deg * kPi / 180;
    expect_near(automatic_up({std::sin(t), 0, -std::cos(t)}, z), {0, 1, 0});
  }
  // Another up: the azimuth-90° axis about it, unit and perpendicular to it.
  const Vec3f x_up = automatic_up({-3, 0, 0}, {1, 0, 0});
  EXPECT_NEAR(norm(x_up), 1, 1e-6);
  EXPECT_NEAR(dot(x_up, {1, 0, 0}), 0, 1e-6);
}

TEST(RenderCamera, TopViewIsAMapWithYUp) {
  const Camera c = looking({0, 0, 3}, {0, 0, 0}, automatic_up({0, 0, -3}, {0, 0, 1}));
  const Projection p = make_projection(c);
  const auto o = project(p, {0, 0, 0}), x = project(p, {1, 0, 0}), y = project(p, {0, 1, 0});
  EXPECT_NEAR(o[0], p.cx, 1e-3);
  EXPECT_NEAR(o[1], p.cy, 1e-3);
  EXPECT_GT(x[0], o[0] + 1);  // +x to the right
  EXPECT_NEAR(x[1], o[1], 1e-3);
  EXPECT_LT(y[1], o[1] - 1);  // +y up (rows grow downwards)
  EXPECT_NEAR(y[0], o[0], 1e-3);
}

TEST(RenderCamera, BottomViewIsTheMapSeenFromBelow) {
  const Camera c = looking({0, 0, -3}, {0, 0, 0}, automatic_up({0, 0, 3}, {0, 0, 1}));
  const Projection p = make_projection(c);
  const auto o = project(p, {0, 0, 0}), x = project(p, {1, 0, 0}), y = project(p, {0, 1, 0});
  EXPECT_LT(x[0], o[0] - 1);  // +x to the left
  EXPECT_LT(y[1], o[1] - 1);  // +y up
}

TEST(RenderCamera, OrbitTopAndBottomViewsMatchEyeCameras) {
  const BoundingSphere b{{1, 2, 3}, 2};
  for (float el : {90.0f, -90.0f})
    for (float az : {0.0f, 35.0f, 200.0f}) {
      const Camera orbit = orbit_camera(b, az, el, 10.0f, {0, 0, 1}, 40, 64, 48);
      const Vec3f eye = b.center + Vec3f{0, 0, el > 0 ? 10.0f : -10.0f};
      const Camera eye_cam = looking(eye, b.center, automatic_up(b.center - eye, {0, 0, 1}));
      const Projection p = make_projection(orbit), q = make_projection(eye_cam);
      expect_near(p.right, q.right);
      expect_near(p.down, q.down);
      expect_near(p.forward, q.forward);
      expect_near(orbit.eye, eye, 1e-4f);
    }
  // Below 89.19° the orbit keeps up itself.
  EXPECT_EQ(orbit_camera(b, 0, 89, 10.0f, {0, 0, 1}, 40, 64, 48).up, (Vec3f{0, 0, 1}));
}

TEST(RenderCamera, UpParallelToTheViewOrientsNothing) {
  EXPECT_FALSE(up_orients_view({0, 0, -3}, {0, 0, 1}));
  EXPECT_FALSE(up_orients_view({0, 0, -3}, {0, 0, -5}));
  EXPECT_FALSE(up_orients_view({0, 0, 0}, {0, 0, 1}));
  EXPECT_TRUE(up_orients_view({0, 0, -3}, {1e-3f, 0, 1}));
  EXPECT_TRUE(up_orients_view({1, 0, 0}, {0, 0, 1}));
  EXPECT_THROW(make_projection(looking({0, 0, 3}, {0, 0, 0}, {0, 0, 1})), Error);
}

TEST(RenderCamera, TurnedTopViewSpinsTheImage) {
  const Vec3f axis{0, 0, 1};
  const Camera top = looking({0, 0, 3}, {0, 0, 0}, automatic_up({0, 0, -3}, axis));
  const Camera quarter = turned_camera(top, axis, 0.5f * kPi);
  expect_near(quarter.eye, top.eye);  // on the axis: the eye stays
  expect_near(quarter.up, {-1, 0, 0});
  // +x, right in the first frame, is down in the second: the model turned with the table.
  const Projection p = make_projection(quarter);
  const auto o = project(p, {0, 0, 0}), x = project(p, {1, 0, 0});
  EXPECT_GT(x[1], o[1] + 1);
  EXPECT_NEAR(x[0], o[0], 1e-3);
  // A whole turntable renders: every frame's camera is valid.
  for (int i = 0; i < 36; ++i)
    EXPECT_NO_THROW(make_projection(turned_camera(top, axis, 2 * kPi * i / 36)));
}

TEST(RenderCamera, TurnedCameraKeepsAnUpAlongTheAxis) {
  const Camera c = looking({3, -2, 1}, {0.5f, 0, 0}, {0, 0, 1});
  const Camera t = turned_camera(c, {0, 0, 1}, 0.7f);
  EXPECT_EQ(t.up, c.up);
  EXPECT_EQ(t.target, c.target);
  EXPECT_NEAR(t.eye.z, c.eye.z, 1e-6);
  const Vec3f d0 = c.eye - c.target, d1 = t.eye - t.target;
  EXPECT_NEAR(std::hypot(d1.x, d1.y), std::hypot(d0.x, d0.y), 1e-5);
  EXPECT_NEAR(std::atan2(d1.y, d1.x) - std::atan2(d0.y, d0.x), 0.7f, 1e-5);
}

// Default views fill the frame with the splats' box: a wide, low building-like box seen from the
// default three-quarter view and from above has every corner inside the image, one of them at the
// margin (the box fills the frame), and the camera is nearer than the bounding sphere's framing
// would put it; without a box the sphere's distance stands.
TEST(RenderCamera, DefaultViewsFillTheFrameWithTheBox) {
  BoundingSphere b;
  b.center = {1, 2, 3};
  b.box_lo = b.center - Vec3f{8, 27, 9};
  b.box_hi = b.center + Vec3f{8, 27, 9};
  b.radius = norm(Vec3f{8, 27, 9});
  for (const std::array<float, 2> view : {std::array<float, 2>{35, 25}, {0, 90}, {200, -30}}) {
    const Camera c = orbit_camera(b, view[0], view[1], std::nullopt, {0, 0, 1}, 40, 1280, 720);
    const Projection p = make_projection(c);
    float edge = 1;  // the least free share of the half-width or half-height over the corners
    for (int k = 0; k < 8; ++k) {
      const Vec3f corner{(k & 1) ? b.box_hi.x : b.box_lo.x, (k & 2) ? b.box_hi.y : b.box_lo.y,
                         (k & 4) ? b.box_hi.z : b.box_lo.z};
      const auto [x, y] = project(p, corner);
      edge = std::min({edge, 1 - std::fabs(x - p.cx) / p.cx, 1 - std::fabs(y - p.cy) / p.cy});
    }
    EXPECT_NEAR(edge, 1 - 1 / 1.08f, 1e-4f) << view[0] << "," << view[1];
    EXPECT_LT(norm(c.eye - c.target), framing_distance(b, 40, 1280, 720));
  }
  BoundingSphere sphere_only = b;
  sphere_only.box_lo = {1, 1, 1};
  sphere_only.box_hi = {-1, -1, -1};
  const Camera c = orbit_camera(sphere_only, 35, 25, std::nullopt, {0, 0, 1}, 40, 1280, 720);
  EXPECT_FLOAT_EQ(norm(c.eye - c.target), framing_distance(b, 40, 1280, 720));
}

}  // namespace
}  // namespace splatkit::render
