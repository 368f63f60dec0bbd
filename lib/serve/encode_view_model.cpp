#include "serve/encode_view_model.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "formats/qsplat_codes.h"
#include "formats/read_cloud.h"
#include "formats/read_qsplat.h"
#include "formats/read_spt.h"
#include "formats/spt_codes.h"
#include "render/qsplat_scene.h"
#include "render/render_scene.h"
#include "render/scene_from_document.h"
#include "render/select_qsplat.h"
#include "render/splat_palette.h"
#include "render/spt_scene.h"
#include "splatkit/input_stream.h"

namespace splatkit::serve {

namespace {

using render::BoundingSphere;
using render::RenderScene;

// The data section under construction and the JSON entries that describe it.
class Arrays {
 public:
  template <class T>
  void add(const std::string& name, const T* data, std::size_t count, const char* type,
           int components) {
    const std::size_t bytes = count * sizeof(T);
    const std::size_t offset = data_.size();
    data_.resize(offset + ((bytes + 3) & ~std::size_t{3}), '\0');
    if (bytes) std::memcpy(data_.data() + offset, data, bytes);
    index_[name] = {
        {"offset", offset}, {"bytes", bytes}, {"type", type}, {"components", components}};
  }
  void add_vec3(const std::string& name, const std::vector<Vec3f>& v) {
    add(name, reinterpret_cast<const float*>(v.data()), v.size() * 3, "f32", 3);
  }
  std::string& data() { return data_; }
  const nlohmann::json& index() const { return index_; }

 private:
  std::string data_;
  nlohmann::json index_ = nlohmann::json::object();
};

static_assert(sizeof(Vec3f) == 12, "Vec3f is three packed floats");

std::string assemble(nlohmann::json header, Arrays& arrays) {
  header["arrays"] = arrays.index();
  std::string text = header.dump();
  std::string out = "SKVIEW1";
  out.push_back('\0');
  const uint32_t length = static_cast<uint32_t>(text.size());
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((length >> (8 * i)) & 0xFF));
  out += text;
  out.resize((out.size() + 3) & ~std::size_t{3}, '\0');
  out += arrays.data();
  return out;
}

nlohmann::json common(const char* kind, const std::string& name, std::size_t count,
                      const BoundingSphere& b, const std::array<double, 3>& origin,
                      float mean_radius) {
  nlohmann::json h = {
      {"kind", kind},     {"name", name},
      {"count", count},   {"bounds", {b.center.x, b.center.y, b.center.z, b.radius}},
      {"origin", origin}, {"mean_radius", mean_radius}};
  if (b.has_box())  // what default views fill the frame with (render/camera.h)
    h["box"] = {b.box_lo.x, b.box_lo.y, b.box_lo.z, b.box_hi.x, b.box_hi.y, b.box_hi.z};
  return h;
}

std::string encode_splats(RenderScene& s, const std::string& name) {
  Arrays a;
  a.add_vec3("position", s.positions);
  a.add_vec3("normal", s.normals);
  a.add("radius", s.radii.data(), s.radii.size(), "f32", 1);
  if (!s.axes.empty() && s.minor_radii.size() == s.size()) {
    a.add_vec3("axis", s.axes);
    a.add("minor", s.minor_radii.data(), s.minor_radii.size(), "f32", 1);
  }
  if (!s.colors.empty()) a.add_vec3("color", s.colors);
  if (!s.surface_ids.empty()) {
    a.add("surface", s.surface_ids.data(), s.surface_ids.size(), "u32", 1);
    a.add_vec3("surface_color", render::surface_colors(s.surface_ids));
  }
  return assemble(common("splats", name, s.size(), s.bounds, s.origin, s.mean_radius), a);
}

int16_t snorm16(float v) {
  return static_cast<int16_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f));
}

std::string encode_spt(const SptModel& m, const RenderScene& s, const std::string& name) {
  constexpr std::size_t kStride = 36;
  std::vector<unsigned char> entries(m.size() * kStride);
  for (std::size_t i = 0; i < m.size(); ++i) {
    unsigned char* e = entries.data() + i * kStride;
    std::memcpy(e, &m.positions[i], 12);
    const int16_t n[4] = {snorm16(m.normals[i].x), snorm16(m.normals[i].y), snorm16(m.normals[i].z),
                          0};
    std::memcpy(e + 12, n, 8);
    const float r_max = std::min(m.r_max[i], 3.4e38f);
    const float f[3] = {m.diameters[i], m.r_min[i], r_max};
    std::memcpy(e + 20, f, 12);
    // Without colours: splat-view's grey albedo, 0.6 linear.
    const std::array<uint8_t, 3> c =
        m.colors.empty() ? std::array<uint8_t, 3>{203, 203, 203} : m.colors[i];
    const unsigned char rgba[4] = {c[0], c[1], c[2], 255};
    std::memcpy(e + 32, rgba, 4);
  }
  Arrays a;
  a.add("entries", entries.data(), entries.size(), "u8", 1);
  nlohmann::json h = common("spt", name, m.size(), s.bounds, m.header.origin, s.mean_radius);
  h["epsilon"] = m.header.epsilon;
  h["leaves"] = m.leaves;
  h["has_color"] = !m.colors.empty();
  h["stride"] = kStride;
  return assemble(std::move(h), a);
}

std::string encode_qsplat(const QSplatModel& m, const RenderScene& s, const std::string& name) {
  Arrays a;
  a.add_vec3("centre", m.centres);
  a.add("radius", m.radii.data(), m.radii.size(), "f32", 1);
  std::vector<Vec3f> normals(m.size());
  std::vector<uint32_t> cones(m.size()), kids(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    normals[i] = qsplat::decode_normal(m.normal_codes[i]);
    cones[i] = m.cones[i];
    kids[i] = m.child_count[i];
  }
  a.add_vec3("normal", normals);
  a.add("cone", cones.data(), cones.size(), "u32", 1);
  a.add("first_child", m.first_child.data(), m.first_child.size(), "u32", 1);
  a.add("child_count", kids.data(), kids.size(), "u32", 1);
  a.add("roots", m.roots.data(), m.roots.size(), "u32", 1);
  if (m.has_color && m.colors.size() == m.size()) {
    const auto& palette = render::linear_palette_565();
    std::vector<Vec3f> colors(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) colors[i] = palette[m.colors[i]];
    a.add_vec3("color", colors);
  }
  nlohmann::json h = common("qsplat", name, m.size(), s.bounds, s.origin, s.mean_radius);
  h["leaves"] = m.leaves;
  return assemble(std::move(h), a);
}

}  // namespace

std::string encode_view_model(const std::string& path, const std::string& name) {
  InputStream in(path);
  if (looks_like_qsplat(in.peek(6))) {
    // The scene holds the model and the sphere splat-view frames it by.
    RenderScene s = render::make_qsplat_scene(read_qsplat(in), name);
    return encode_qsplat(*s.qsplat, s, name);
  }
  if (spt::looks_like_spt(in.peek(8))) {
    RenderScene s = render::make_spt_scene(read_spt(in), name);
    return encode_spt(*s.spt, s, name);
  }
  render::DocumentScene d = render::scene_from_document(read_cloud(in), name);
  return encode_splats(d.scene, name);
}

}  // namespace splatkit::serve
