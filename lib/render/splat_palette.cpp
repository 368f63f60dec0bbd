#include "render/splat_palette.h"

#include <cmath>

#include "render/framebuffer.h"
#include "render/render_scene.h"

namespace splatkit::render {

namespace {

// HSV (all in [0, 1]) to sRGB-encoded RGB.
Vec3f hsv(float h, float s, float v) {
  const float h6 = 6.0f * (h - std::floor(h));
  const int sector = static_cast<int>(h6) % 6;
  const float f = h6 - std::floor(h6);
  const float p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (sector) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

Vec3f linear(const Vec3f& srgb) {
  return {srgb_to_linear(srgb.x), srgb_to_linear(srgb.y), srgb_to_linear(srgb.z)};
}

}  // namespace

Vec3f surface_color(uint32_t id) {
  if (id == kNoSurfaceId) return linear({0.5f, 0.5f, 0.5f});
  constexpr double kGolden = 0.6180339887498949;
  const double hue = std::fmod(0.05 + kGolden * id, 1.0);
  static constexpr float kSaturation[3] = {0.75f, 0.5f, 0.9f};
  static constexpr float kValue[3] = {0.95f, 0.85f, 0.7f};
  return linear(hsv(static_cast<float>(hue), kSaturation[id % 3], kValue[(id / 3) % 3]));
}

std::vector<Vec3f> surface_colors(std::span<const uint32_t> ids) {
  std::vector<Vec3f> out(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) out[i] = surface_color(ids[i]);
  return out;
}

std::vector<Vec3f> sharp_colors(std::span<const graph::SplatClass> classes) {
  const Vec3f red = linear({0.9f, 0.1f, 0.1f}), green = linear({0.2f, 0.75f, 0.25f});
  std::vector<Vec3f> out(classes.size());
  for (std::size_t i = 0; i < classes.size(); ++i)
    out[i] = classes[i] == graph::SplatClass::kSmooth ? green : red;
  return out;
}

std::vector<Vec3f> clipped_colors(const graph::ClipPartnerTable& table) {
  const Vec3f orange = linear({1.0f, 0.45f, 0.0f}), grey = linear({0.75f, 0.75f, 0.75f});
  std::vector<Vec3f> out(table.num_splats());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = table.has_partners(i) ? orange : grey;
  return out;
}

}  // namespace splatkit::render
