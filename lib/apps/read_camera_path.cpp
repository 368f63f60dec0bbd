#include "apps/read_camera_path.h"

#include <nlohmann/json.hpp>

#include <cmath>

#include "splatkit/error.h"

namespace splatkit::apps {

namespace {

// `origin` is subtracted (zero for directions).
Vec3f vec3(const nlohmann::json& e, const char* key, const std::string& name, std::size_t i,
           const std::array<double, 3>& origin = {0, 0, 0}) {
  const auto& v = e.at(key);
  auto bad = [&]() -> Vec3f {
    throw_bad_input(name, "camera " + std::to_string(i) + ": \"" + key +
                              "\" must be an array of three finite numbers");
  };
  if (!v.is_array() || v.size() != 3) return bad();
  Vec3f out;
  float* c[3] = {&out.x, &out.y, &out.z};
  for (int k = 0; k < 3; ++k) {
    if (!v[k].is_number()) return bad();
    const double d = v[k].get<double>();
    if (!std::isfinite(d) || std::fabs(d - origin[k]) > 3e38) return bad();
    *c[k] = static_cast<float>(d - origin[k]);
  }
  return out;
}

}  // namespace

std::vector<render::Camera> read_camera_path(const std::string& text, const std::string& name,
                                             const Vec3f& default_up, float default_fov, int width,
                                             int height, const std::array<double, 3>& origin) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw_bad_input(name, std::string("not a JSON camera path: ") + e.what());
  }
  if (!doc.is_array() || doc.empty())
    throw_bad_input(name, "a camera path must be a non-empty JSON array of cameras");
  std::vector<render::Camera> cameras;
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const auto& e = doc[i];
    const std::string where = "camera " + std::to_string(i);
    if (!e.is_object()) throw_bad_input(name, where + ": not a JSON object");
    for (const auto& item : e.items())
      if (item.key() != "eye" && item.key() != "target" && item.key() != "up" &&
          item.key() != "fov")
        throw_bad_input(name,
                        where + ": unknown key \"" + item.key() + "\" (eye, target, up, fov)");
    if (!e.contains("eye") || !e.contains("target"))
      throw_bad_input(name, where + ": needs \"eye\" and \"target\"");
    render::Camera c;
    c.eye = vec3(e, "eye", name, i, origin);
    c.target = vec3(e, "target", name, i, origin);
    c.width = width;
    c.height = height;
    c.fov_y_deg = default_fov;
    if (e.contains("fov")) {
      if (!e["fov"].is_number()) throw_bad_input(name, where + ": \"fov\" must be a number");
      const double f = e["fov"].get<double>();
      if (!(f > 0 && f < 180)) throw_bad_input(name, where + ": \"fov\" must be in (0, 180)");
      c.fov_y_deg = static_cast<float>(f);
    }
    if (c.eye == c.target) throw_bad_input(name, where + ": eye and target are the same point");
    if (e.contains("up")) {
      c.up = vec3(e, "up", name, i);
      if (!render::up_orients_view(c.target - c.eye, c.up))
        throw_bad_input(name, where + ": \"up\" is zero or parallel to the viewing direction");
    } else {
      c.up = render::automatic_up(c.target - c.eye, default_up);
    }
    cameras.push_back(c);
  }
  return cameras;
}

}  // namespace splatkit::apps
