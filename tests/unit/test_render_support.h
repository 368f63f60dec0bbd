// Test support for the renderer tests: splat samplings of a sphere and a torus (make_shape), and a
// small analytic ray tracer that renders the exact shapes with the same camera and the same
// shading, plus the image comparisons the tests assert (holes, silhouettes, PSNR).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/frame_renderer.h"
#include "render/render_scene.h"
#include "render/shade_pixel.h"
#include "splatkit/splat_cloud.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::render::testing {

inline constexpr double kPi = std::numbers::pi;

enum class Shape { kSphere, kTorus };

// Unit sphere at the origin; torus about +z with major radius 1, minor radius 0.35 (the shapes
// of make_shape()).
inline constexpr double kTorusMajor = 1.0, kTorusMinor = 0.35;

// About `n` stratified samples from make_shape() (exact outward normals, radii from the
// sampling density), without colours so that the default albedo matches the reference.
inline SplatCloud sample_shape(Shape shape, int n) {
  ShapeOptions o;
  o.kind = shape == Shape::kSphere ? ShapeKind::kSphere : ShapeKind::kTorus;
  o.points = static_cast<std::size_t>(n);
  SplatCloud c = make_shape(o);
  c.colors.clear();
  return c;
}

// Exact ray casting of the analytic shape: depth along the forward axis of the first hit.
struct Hit {
  double t;  // ray parameter with the forward component of the direction equal to 1
  Vec3f normal;
};

inline std::optional<Hit> intersect(Shape shape, const double o[3], const double d[3]) {
  auto dotd = [](const double* a, const double* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  const double dd = dotd(d, d);
  // Both shapes fit in a sphere of radius 1.35: find the entry into it first.
  const double bound = shape == Shape::kSphere ? 1.0 : kTorusMajor + kTorusMinor;
  const double b = dotd(o, d), c = dotd(o, o) - bound * bound;
  const double disc = b * b - dd * c;
  if (disc < 0) return std::nullopt;
  double t = (-b - std::sqrt(disc)) / dd;
  if (shape == Shape::kSphere) {
    if (t <= 0) return std::nullopt;
    double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    return Hit{t, {float(p[0]), float(p[1]), float(p[2])}};
  }
  const double t_exit = (-b + std::sqrt(disc)) / dd;
  const double len = std::sqrt(dd);
  for (int k = 0; k < 2000 && t <= t_exit; ++k) {
    double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    const double q = std::hypot(p[0], p[1]) - kTorusMajor;
    const double sdf = std::hypot(q, p[2]) - kTorusMinor;
    if (sdf < 1e-10) {
      const double ring = std::hypot(p[0], p[1]);
      const double cx = p[0] / ring * kTorusMajor, cy = p[1] / ring * kTorusMajor;
      double n[3] = {p[0] - cx, p[1] - cy, p[2]};
      const double nl = std::sqrt(dotd(n, n));
      return Hit{t, {float(n[0] / nl), float(n[1] / nl), float(n[2] / nl)}};
    }
    t += sdf / len;
  }
  return std::nullopt;
}

struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<uint8_t> mask;  // 1 where the shape is hit
  std::vector<float> rgb;     // display values in [0, 1] (sRGB-encoded for phong)
};

// Ray traces `shape` with `camera`, shading each hit with the renderer's shade_pixel.
inline ReferenceImage ray_trace(Shape shape, const Camera& camera, const Shading& shading) {
  ReferenceImage img;
  img.width = camera.width;
  img.height = camera.height;
  img.mask.assign(std::size_t(camera.width) * camera.height, 0);
  img.rgb.assign(img.mask.size() * 3, 0.0f);
  // The camera frame in double, built here independently of make_projection.
  const double e[3] = {camera.eye.x, camera.eye.y, camera.eye.z};
  double f[3] = {camera.target.x - e[0], camera.target.y - e[1], camera.target.z - e[2]};
  const double fl = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (double& v : f) v /= fl;
  const double u[3] = {camera.up.x, camera.up.y, camera.up.z};
  double r[3] = {f[1] * u[2] - f[2] * u[1], f[2] * u[0] - f[0] * u[2], f[0] * u[1] - f[1] * u[0]};
  const double rl = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  for (double& v : r) v /= rl;
  const double dn[3] = {f[1] * r[2] - f[2] * r[1], f[2] * r[0] - f[0] * r[2],
                        f[0] * r[1] - f[1] * r[0]};
  const double focal = 0.5 * camera.height / std::tan(0.5 * camera.fov_y_deg * kPi / 180);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double sx = (x + 0.5 - 0.5 * camera.width) / focal;
      const double sy = (y + 0.5 - 0.5 * camera.height) / focal;
      const double d[3] = {f[0] + sx * r[0] + sy * dn[0], f[1] + sx * r[1] + sy * dn[1],
                           f[2] + sx * r[2] + sy * dn[2]};
      auto hit = intersect(shape, e, d);
      if (!hit) continue;
      const std::size_t p = std::size_t(y) * camera.width + x;
      img.mask[p] = 1;
      const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const Vec3f view{float(-d[0] / dl), float(-d[1] / dl), float(-d[2] / dl)};
      Vec3f c =
          shade_pixel(shading, hit->normal, view, RenderOptions{}.default_albedo, float(hit->t));
      if (shading.linear_output)
        c = {linear_to_srgb(c.x), linear_to_srgb(c.y), linear_to_srgb(c.z)};
      img.rgb[3 * p] = c.x;
      img.rgb[3 * p + 1] = c.y;
      img.rgb[3 * p + 2] = c.z;
    }
  return img;
}

// 3×3 erosion (dilate = false) or dilation of a 0/1 mask; outside the image counts as 0.
inline std::vector<uint8_t> morph(const std::vector<uint8_t>& m, int w, int h, bool dilate) {
  std::vector<uint8_t> out(m.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool all = true, any = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          const bool v = xx >= 0 && yy >= 0 && xx < w && yy < h && m[std::size_t(yy) * w + xx];
          all = all && v;
          any = any || v;
        }
      out[std::size_t(y) * w + x] = dilate ? any : all;
    }
  return out;
}

// A level-of-detail render `b` against the plain splat render `a` of the same cloud (same camera,
// rgb8 and alpha planes): pixels of a's mask, holes (pixels of the eroded mask b leaves empty) and
// the PSNR (dB) of the 8-bit colours inside the mask.
struct MaskComparison {
  int pixels = 0, holes = 0;
  double psnr = 0;
};
inline MaskComparison compare_inside_mask(const Framebuffer& a, const Framebuffer& b, int w,
                                          int h) {
  MaskComparison c;
  std::vector<uint8_t> mask(a.alpha.size());
  for (std::size_t p = 0; p < mask.size(); ++p) mask[p] = a.alpha[p] > 0;
  const auto eroded = morph(mask, w, h, false);
  double se = 0;
  for (std::size_t p = 0; p < mask.size(); ++p) {
    c.holes += eroded[p] && !(b.alpha[p] > 0);
    if (!mask[p]) continue;
    ++c.pixels;
    for (int k = 0; k < 3; ++k) {
      const double e = static_cast<double>(a.rgb8[3 * p + k]) - b.rgb8[3 * p + k];
      se += e * e;
    }
  }
  const double mse = se / (3.0 * std::max(1, c.pixels));
  c.psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;
  return c;
}

struct Comparison {
  int holes = 0;    // reference pixels (mask eroded by 1 px) the splats leave uncovered
  int outside = 0;  // splat pixels farther than 1 px from the reference mask
  int mask_pixels = 0;
  double psnr = 0;  // over the reference mask, 8-bit values
};

inline Comparison compare(const ReferenceImage& ref, const Framebuffer& fb) {
  Comparison c;
  const int w = ref.width, h = ref.height;
  const auto eroded = morph(ref.mask, w, h, false);
  const auto dilated = morph(ref.mask, w, h, true);
  double se = 0;
  for (std::size_t p = 0; p < ref.mask.size(); ++p) {
    const bool covered = fb.alpha[p] > 0;
    c.holes += eroded[p] && !covered;
    c.outside += covered && !dilated[p];
    if (!ref.mask[p]) continue;
    ++c.mask_pixels;
    for (int k = 0; k < 3; ++k) {
      const double e = std::round(ref.rgb[3 * p + k] * 255.0) - fb.rgb8[3 * p + k];
      se += e * e;
    }
  }
  const double mse = se / (3.0 * std::max(1, c.mask_pixels));
  c.psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;
  return c;
}

// With SPLATKIT_RENDER_TEST_DUMP=<dir> set, writes <dir>/<file>, a binary PPM of width × height
// pixels whose i-th byte is byte(i), for looking at the pictures; does nothing otherwise.
template <class Byte>
void dump_ppm(const std::string& file, int width, int height, Byte&& byte) {
  const char* dir = std::getenv("SPLATKIT_RENDER_TEST_DUMP");
  if (!dir) return;
  FILE* f = std::fopen((std::string(dir) + "/" + file).c_str(), "wb");
  if (!f) return;
  std::fprintf(f, "P6\n%d %d\n255\n", width, height);
  for (std::size_t i = 0; i < std::size_t(width) * std::size_t(height) * 3; ++i)
    std::fputc(byte(i), f);
  std::fclose(f);
}

// <name>_splats.ppm and <name>_reference.ppm (dump_ppm).
inline void dump_images(const std::string& name, const ReferenceImage& ref, const Framebuffer& fb) {
  dump_ppm(name + "_splats.ppm", ref.width, ref.height, [&](std::size_t i) { return fb.rgb8[i]; });
  dump_ppm(name + "_reference.ppm", ref.width, ref.height,
           [&](std::size_t i) { return int(std::round(ref.rgb[i] * 255.0)); });
}

}  // namespace splatkit::render::testing
