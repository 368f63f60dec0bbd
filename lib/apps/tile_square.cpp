#include "apps/tile_square.h"

#include <cmath>

namespace splatkit::apps {

std::optional<TileSquare> tile_square(const nlohmann::json& metadata) {
  if (!metadata.is_object() || !metadata.contains("tile")) return std::nullopt;
  try {
    const nlohmann::json& tile = metadata.at("tile");
    TileSquare t;
    for (int a = 0; a < 2; ++a) {
      t.lo[a] = tile.at("square").at("min").at(a).get<double>();
      t.hi[a] = tile.at("square").at("max").at(a).get<double>();
    }
    t.halo = tile.at("halo").get<double>();
    if (!std::isfinite(t.lo[0] + t.lo[1] + t.hi[0] + t.hi[1] + t.halo) || !(t.halo >= 0) ||
        !(t.lo[0] < t.hi[0]) || !(t.lo[1] < t.hi[1]))
      return std::nullopt;
    if (tile.contains("skyline") && tile.at("skyline").is_object()) t.skyline = &tile.at("skyline");
    return t;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

bool survey_goes_on(const TileSquare& tile, int side) {
  if (tile.skyline == nullptr) return true;
  const auto it = tile.skyline->find(kTileSides[side]);
  if (it == tile.skyline->end() || !it->is_array()) return false;
  for (const nlohmann::json& top : *it)
    if (top.is_number()) return true;
  return false;
}

}  // namespace splatkit::apps
