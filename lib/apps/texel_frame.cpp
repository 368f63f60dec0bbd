#include "apps/texel_frame.h"

#include <cmath>
#include <vector>

namespace splatkit::apps {

TexelFrame texel_frame(const nlohmann::json& geo) {
  TexelFrame f;
  if (!geo.is_object()) return f;
  auto numbers = [&](const char* key, std::size_t n) {
    std::vector<double> v;
    const auto it = geo.find(key);
    if (it == geo.end() || !it->is_array() || it->size() < n) return v;
    for (const auto& x : *it) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) return std::vector<double>{};
      v.push_back(x.get<double>());
    }
    return v;
  };
  const double area = geo.value("raster_type", std::string("area")) == "point" ? 0.0 : 0.5;
  const std::vector<double> scale = numbers("pixel_scale", 2), tie = numbers("tiepoint", 6),
                            origin = numbers("origin", 2), m = numbers("transformation", 16);
  TexelFrame g;
  if (scale.size() >= 2 && scale[0] > 0 && scale[1] > 0 && tie.size() >= 6) {
    g = {tie[3] + (area - tie[0]) * scale[0], scale[0], tie[4] - (area - tie[1]) * scale[1],
         -scale[1], ""};
  } else if (scale.size() >= 2 && scale[0] > 0 && scale[1] > 0 && origin.size() >= 2) {
    g = {origin[0], scale[0], origin[1], -scale[1], ""};  // SRTM: the north-west sample
  } else if (m.size() >= 16 && m[1] == 0 && m[4] == 0 && m[0] != 0 && m[5] != 0) {
    g = {m[3] + area * m[0], m[0], m[7] + area * m[5], m[5], ""};
  } else {
    return f;
  }
  const std::string crs = geo.value("crs", std::string());
  g.name = crs == "EPSG:4326"
               ? "EPSG:4326: x = longitude, y = latitude (degrees), z = height"
               : (crs.empty() ? std::string("the map's") : crs) + ": x, y projected, z = height";
  return g;
}

}  // namespace splatkit::apps
