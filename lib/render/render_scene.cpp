#include "render/render_scene.h"

#include "formats/read_qsplat.h"
#include "formats/read_spt.h"

#include <algorithm>
#include <cmath>

#include "graph/make_clip_planes.h"
#include "render/splat_bounds.h"
#include "splatkit/check_splats.h"
#include "splatkit/error.h"

namespace splatkit::render {

std::size_t RenderScene::size() const {
  return qsplat ? qsplat->leaves : spt ? spt->leaves : positions.size();
}

float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::vector<Vec3f> linear_colors(const SplatCloud& cloud) {
  std::vector<Vec3f> out;
  if (!cloud.has_colors()) return out;
  const int levels = (1 << cloud.color_bits) - 1;
  // A table per code value: 8-bit clouds need 256 entries, 16-bit ones 65536.
  std::vector<float> table(static_cast<std::size_t>(levels) + 1);
  for (int i = 0; i <= levels; ++i) table[i] = srgb_to_linear(static_cast<float>(i) / levels);
  out.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& c = cloud.colors[i];
    auto at = [&](uint16_t v) { return table[std::min<int>(v, levels)]; };
    out[i] = {at(c[0]), at(c[1]), at(c[2])};
  }
  return out;
}

}  // namespace

RenderScene make_render_scene(SplatCloud&& cloud, const std::string& name) {
  if (cloud.size() == 0) throw_bad_input(name, "the cloud has no points; nothing to render");
  check_splats(cloud, name);
  RenderScene s;
  s.colors = linear_colors(cloud);
  s.origin = cloud.origin;
  s.positions = std::move(cloud.positions);
  s.normals = std::move(cloud.normals);
  s.radii = std::move(cloud.radii);
  s.axes = std::move(cloud.axes);
  s.minor_radii = std::move(cloud.minor_radii);
  double sum = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.normals[i] = normalized(s.normals[i]);
    if (!s.axes.empty())  // exactly in the plane and of unit length, as the rasteriser assumes
      s.axes[i] = normalized(s.axes[i] - s.normals[i] * dot(s.axes[i], s.normals[i]));
    sum += s.radii[i];
    s.max_radius = std::max(s.max_radius, s.radii[i]);
  }
  if (const ExtraAttribute* ids = cloud.find_extra("surface_id")) {
    s.surface_ids.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      double v = ids->values[i];
      if (!(v >= 0 && v <= 4294967295.0))
        throw_bad_input(name, "splat " + std::to_string(i) + " has surface_id " +
                                  std::to_string(v) + "; ids must be in [0, 2^32)");
      s.surface_ids[i] = static_cast<uint32_t>(v);
    }
  }
  s.mean_radius = static_cast<float>(sum / s.size());
  s.bounds = splat_bounds(s.size(), [&](std::size_t i, Vec3f& c, float& r) {
    c = s.positions[i];
    r = s.radii[i];
    return true;
  });
  return s;
}

void attach_clip_partners(RenderScene& scene, graph::ClipPartnerTable table,
                          const std::string& name) {
  if (table.num_splats() != scene.size())
    throw_bad_input(name, "the clip partner table has " + std::to_string(table.num_splats()) +
                              " rows for " + std::to_string(scene.size()) + " splats");
  try {
    table.check_consistent();
  } catch (const std::logic_error& e) {
    throw_bad_input(name, std::string("clip partner table: ") + e.what());
  }
  scene.clip_planes = graph::make_clip_planes(table, scene.positions, scene.normals);
  scene.clip = std::move(table);
}

}  // namespace splatkit::render
