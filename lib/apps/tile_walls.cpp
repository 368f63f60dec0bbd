#include "apps/tile_walls.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace splatkit::apps {

std::vector<VisibilityWall> tile_walls(const nlohmann::json& metadata, const SplatCloud& cloud) {
  std::vector<VisibilityWall> walls;
  if (cloud.size() == 0 || !metadata.is_object() || !metadata.contains("tile")) return walls;
  try {
    const nlohmann::json& tile = metadata.at("tile");
    const double lo[2] = {tile.at("square").at("min").at(0).get<double>(),
                          tile.at("square").at("min").at(1).get<double>()};
    const double hi[2] = {tile.at("square").at("max").at(0).get<double>(),
                          tile.at("square").at("max").at(1).get<double>()};
    const double halo = tile.at("halo").get<double>();
    if (!std::isfinite(lo[0] + lo[1] + hi[0] + hi[1] + halo) || !(halo >= 0) || !(lo[0] < hi[0]) ||
        !(lo[1] < hi[1]))
      return walls;
    float bottom = cloud.positions[0].z;
    for (const Vec3f& p : cloud.positions) bottom = std::min(bottom, p.z);
    // The halo's outer edge, in the local frame.
    const double ox = cloud.origin[0], oy = cloud.origin[1], oz = cloud.origin[2];
    const float x0 = static_cast<float>(lo[0] - halo - ox),
                x1 = static_cast<float>(hi[0] + halo - ox);
    const float y0 = static_cast<float>(lo[1] - halo - oy),
                y1 = static_cast<float>(hi[1] + halo - oy);
    // Per side: where its segments start and the direction along it (the order of the skyline's
    // segments: increasing y on the x sides, increasing x on the y sides).
    const char* const names[4] = {"-x", "+x", "-y", "+y"};
    const Vec3f start[4] = {{x0, y0, bottom}, {x1, y0, bottom}, {x0, y0, bottom}, {x0, y1, bottom}};
    const Vec3f dir[4] = {{0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {1, 0, 0}};
    const float span[4] = {y1 - y0, y1 - y0, x1 - x0, x1 - x0};
    const nlohmann::json& skyline = tile.at("skyline");
    for (int s = 0; s < 4; ++s) {
      if (!skyline.contains(names[s])) continue;
      const nlohmann::json& tops = skyline.at(names[s]);
      const std::size_t count = tops.size();
      if (count == 0 || count > 4096) continue;
      const float length = span[s] / static_cast<float>(count);
      const float step = std::max(span[s], 0.0f) / 64;
      for (std::size_t k = 0; k < count; ++k) {
        if (!tops[k].is_number()) continue;
        const float z = static_cast<float>(tops[k].get<double>() - oz);
        if (!(z > bottom) || !std::isfinite(z)) continue;
        walls.push_back(
            {start[s] + dir[s] * (length * static_cast<float>(k)), dir[s] * length, z, step});
      }
    }
  } catch (const nlohmann::json::exception&) {
    walls.clear();
  }
  return walls;
}

}  // namespace splatkit::apps
