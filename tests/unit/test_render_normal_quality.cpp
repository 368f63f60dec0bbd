// The frame renderer's per-pixel normals against analytic ones (the AOV splat-view writes to EXR
// as N.X, N.Y, N.Z):
//   - a unit sphere of 3,000 i.i.d. samples with exact normals: mean error <= 0.3°, 95th
//     percentile <= 1° over the pixels seen at less than 75° from the normal; with
//     estimate_normals' own normals: mean <= 1°;
//   - a thin wedge (two planes meeting at 20°, a knife edge) seen from above its top face: the
//     bottom face lies within the Z-threshold behind the top near the edge and faces away; every
//     pixel's normal is the top face's;
//   - a crevice (two planes meeting at a sharp concave angle) seen from its open side: the walls
//     meet within the Z-threshold at the bottom; no pixel is darker than the darker wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "normals/estimate_normals.h"
#include "test_render_support.h"

namespace splatkit::render {
namespace {

constexpr double kDeg = 180.0 / testing::kPi;

struct ErrorStats {
  std::size_t pixels = 0, empty = 0;
  double mean = 0, p95 = 0;
};

// Angles between the framebuffer's normals and the unit sphere's at the pixels whose ray meets
// the sphere at a view angle below `max_view_deg`.
ErrorStats sphere_normal_error(const Framebuffer& fb, const Projection& pr, double max_view_deg) {
  std::vector<double> errors;
  ErrorStats s;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const Vec3f rf = pr.ray(x + 0.5f, y + 0.5f);
      const double d[3] = {rf.x, rf.y, rf.z}, o[3] = {pr.eye.x, pr.eye.y, pr.eye.z};
      const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
      const double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1;
      const double disc = b * b - dd * c;
      if (disc < 0) continue;
      const double t = (-b - std::sqrt(disc)) / dd;
      const double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
      const double cos_view = -(p[0] * d[0] + p[1] * d[1] + p[2] * d[2]) / std::sqrt(dd);
      if (std::acos(std::clamp(cos_view, -1.0, 1.0)) * kDeg >= max_view_deg) continue;
      const float* n = &fb.normal[3 * (std::size_t(y) * fb.width + x)];
      if (n[0] == 0 && n[1] == 0 && n[2] == 0) {
        ++s.empty;
        continue;
      }
      const double cosang = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
      errors.push_back(std::acos(std::clamp(cosang, -1.0, 1.0)) * kDeg);
    }
  s.pixels = errors.size();
  if (errors.empty()) return s;
  for (double e : errors) s.mean += e;
  s.mean /= errors.size();
  std::sort(errors.begin(), errors.end());
  s.p95 = errors[std::size_t(0.95 * errors.size())];
  return s;
}

Camera sphere_camera() {
  Camera cam;
  cam.width = 1280;
  cam.height = 720;
  cam.eye = {2.18f, -1.36f, 1.5f};
  cam.target = {0, 0, 0};
  cam.up = {0, 0, 1};
  return cam;
}

ErrorStats render_sphere(SplatCloud cloud, BlendMode blend) {
  RenderScene scene = make_render_scene(std::move(cloud), "sphere");
  RenderOptions options;
  options.blend = blend;
  options.planes = {false, false, true};
  Framebuffer fb;
  FrameRenderer renderer;
  const Camera cam = sphere_camera();
  renderer.render(scene, cam, options, fb);
  return sphere_normal_error(fb, make_projection(cam), 75);
}

SplatCloud random_sphere() {
  ShapeOptions o;
  o.kind = ShapeKind::kSphere;
  o.points = 3000;
  o.random = true;
  SplatCloud c = make_shape(o);
  c.colors.clear();
  return c;
}

TEST(RenderNormalQuality, RandomSphereWithExactNormals) {
  const ErrorStats s = render_sphere(random_sphere(), BlendMode::kZThreshold);
  std::printf("exact normals: %zu pixels, mean %.3f deg, p95 %.3f deg\n", s.pixels, s.mean, s.p95);
  EXPECT_GT(s.pixels, 300000u);
  EXPECT_EQ(s.empty, 0u);
  EXPECT_LE(s.mean, 0.3);
  EXPECT_LE(s.p95, 1.0);
}

TEST(RenderNormalQuality, RandomSphereWithEstimatedNormals) {
  SplatCloud cloud = random_sphere();
  estimate_normals(cloud, NormalOptions{});
  const ErrorStats s = render_sphere(std::move(cloud), BlendMode::kZThreshold);
  std::printf("estimated normals: %zu pixels, mean %.3f deg, p95 %.3f deg\n", s.pixels, s.mean,
              s.p95);
  EXPECT_GT(s.pixels, 300000u);
  EXPECT_EQ(s.empty, 0u);
  EXPECT_LE(s.mean, 1.0);
}

// Samples of the parallelogram origin + s·u + t·v, s, t in [0, 1) (|u|, |v| <= 1.1), on a
// jittered grid of `cells` × `cells`, with normal `n` and radii that cover it (the same for
// every plane).
void add_plane(SplatCloud& c, const Vec3f& origin, const Vec3f& u, const Vec3f& v, const Vec3f& n,
               int cells, std::mt19937& rng) {
  std::uniform_real_distribution<float> jitter(0.2f, 0.8f);
  const float h = 1.1f / cells;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j) {
      const float s = (i + jitter(rng)) / cells, t = (j + jitter(rng)) / cells;
      c.positions.push_back(origin + u * s + v * t);
      c.normals.push_back(n);
      c.radii.push_back(1.1f * h);
    }
}

struct PlanesRender {
  Framebuffer fb;
  Projection projection;
  Shading shading;
};

PlanesRender render_planes(SplatCloud cloud, const Vec3f& eye, const Vec3f& target) {
  RenderScene scene = make_render_scene(std::move(cloud), "planes");
  RenderOptions options;
  options.planes = {false, false, true};
  Camera cam;
  cam.width = 400;
  cam.height = 300;
  cam.eye = eye;
  cam.target = target;
  cam.up = {0, 1, 0};
  PlanesRender r;
  FrameRenderer renderer;
  renderer.render(scene, cam, options, r.fb);
  r.projection = make_projection(cam);
  r.shading = make_shading(ShadeMode::kPhong, r.projection, scene.bounds);
  return r;
}

// A knife edge along y at x = 0: the top face z = 0 (normal +z) and the bottom face
// z = −x·tan 20° (outward normal −(sin 20°, 0, cos 20°)), x in [0, 1]. Seen from above, the bottom
// faces away and lies within the Z-threshold behind the top for x up to a few splat radii.
TEST(RenderNormalQuality, ThinWedgeShowsOnlyItsFrontFace) {
  const float a = 20.0f / float(kDeg);
  SplatCloud c;
  std::mt19937 rng(3);
  add_plane(c, {0, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 40, rng);
  add_plane(c, {0, -0.5f, 0}, {1, 0, -std::tan(a)}, {0, 1, 0}, {-std::sin(a), 0, -std::cos(a)}, 40,
            rng);
  const PlanesRender r = render_planes(std::move(c), {0.3f, 0, 1.6f}, {0.3f, 0, 0});
  // The pixels whose ray meets the top face at x in [0.003, 1], |y| < 0.45: up to the edge, but
  // not beyond it, where the bottom's splats may reach out further than the top's.
  int checked = 0, off = 0;
  const Vec3f eye = r.projection.eye;
  for (int y = 0; y < r.fb.height; ++y)
    for (int x = 0; x < r.fb.width; ++x) {
      const Vec3f d = r.projection.ray(x + 0.5f, y + 0.5f);
      const Vec3f hit = eye + d * (-eye.z / d.z);
      if (hit.x < 0.003f || hit.x > 1 || std::fabs(hit.y) > 0.45f) continue;
      const std::size_t p = std::size_t(y) * r.fb.width + x;
      ASSERT_EQ(r.fb.alpha[p], 1);
      ++checked;
      const float* n = &r.fb.normal[3 * p];
      off += !(n[2] > std::cos(0.5f / float(kDeg)));  // within half a degree of +z
    }
  std::printf("wedge: %d pixels checked, %d off the top face's normal\n", checked, off);
  EXPECT_GT(checked, 30000);
  EXPECT_EQ(off, 0);
}

// A crevice along y: walls from the bottom line x = z = 0 up to z = 1 at x = ±tan 15° (30° apart),
// normals into the groove. Seen from above its opening, both walls face the eye, and near the
// bottom each wall's splats reach behind the other within the Z-threshold. No pixel may shade
// darker (Lambert term of the frame's light) than the darker wall.
TEST(RenderNormalQuality, CreviceIsNoDarkerThanItsWalls) {
  const float a = 15.0f / float(kDeg);
  SplatCloud c;
  std::mt19937 rng(5);
  const Vec3f na{-std::cos(a), 0, std::sin(a)}, nb{std::cos(a), 0, std::sin(a)};
  add_plane(c, {0, -0.5f, 0}, {std::tan(a), 0, 1}, {0, 1, 0}, na, 40, rng);
  add_plane(c, {0, -0.5f, 0}, {-std::tan(a), 0, 1}, {0, 1, 0}, nb, 40, rng);
  const PlanesRender r = render_planes(std::move(c), {0.05f, 0.1f, 3.0f}, {0, 0, 0.3f});
  const Vec3f l = r.shading.light;
  const float darkest = std::min(std::max(0.0f, dot(na, l)), std::max(0.0f, dot(nb, l)));
  int covered = 0, darker = 0;
  for (int y = 0; y < r.fb.height; ++y)
    for (int x = 0; x < r.fb.width; ++x) {
      const std::size_t p = std::size_t(y) * r.fb.width + x;
      if (r.fb.alpha[p] == 0) continue;
      ++covered;
      Vec3f n{r.fb.normal[3 * p], r.fb.normal[3 * p + 1], r.fb.normal[3 * p + 2]};
      // Two-sided as shade_pixel is.
      const Vec3f view = normalized(r.projection.ray(x + 0.5f, y + 0.5f)) * -1.0f;
      if (dot(n, view) < 0) n = n - view * (2 * dot(n, view));
      darker += std::max(0.0f, dot(n, l)) < darkest - 0.01f;
    }
  std::printf("crevice: %d pixels covered, %d darker than the darker wall\n", covered, darker);
  EXPECT_GT(covered, 15000);
  EXPECT_EQ(darker, 0);
}

}  // namespace
}  // namespace splatkit::render
