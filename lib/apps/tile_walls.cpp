#include "apps/tile_walls.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "apps/tile_square.h"

namespace splatkit::apps {

std::vector<VisibilityWall> tile_walls(const nlohmann::json& metadata, const SplatCloud& cloud) {
  std::vector<VisibilityWall> walls;
  const std::optional<TileSquare> tile = tile_square(metadata);
  if (cloud.size() == 0 || !tile || tile->skyline == nullptr) return walls;
  const double* lo = tile->lo;
  const double* hi = tile->hi;
  const double halo = tile->halo;
  float bottom = cloud.positions[0].z;
  for (const Vec3f& p : cloud.positions) bottom = std::min(bottom, p.z);
  // The halo's outer edge, in the local frame.
  const double ox = cloud.origin[0], oy = cloud.origin[1], oz = cloud.origin[2];
  const float x0 = static_cast<float>(lo[0] - halo - ox), x1 = static_cast<float>(hi[0] + halo - ox);
  const float y0 = static_cast<float>(lo[1] - halo - oy), y1 = static_cast<float>(hi[1] + halo - oy);
  // Per side: where its segments start and the direction along it (the order of the skyline's
  // segments: increasing y on the x sides, increasing x on the y sides).
  const Vec3f start[4] = {{x0, y0, bottom}, {x1, y0, bottom}, {x0, y0, bottom}, {x0, y1, bottom}};
  const Vec3f dir[4] = {{0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {1, 0, 0}};
  const float span[4] = {y1 - y0, y1 - y0, x1 - x0, x1 - x0};
  for (int s = 0; s < 4; ++s) {
    const auto side = tile->skyline->find(kTileSides[s]);
    if (side == tile->skyline->end() || !side->is_array()) continue;
    const nlohmann::json& tops = *side;
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
  return walls;
}

}  // namespace splatkit::apps
