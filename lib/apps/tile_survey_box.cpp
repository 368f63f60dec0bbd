#include "apps/tile_survey_box.h"

#include <cmath>

namespace splatkit::apps {

namespace {

const nlohmann::json* find_tile(const nlohmann::json& metadata) {
  if (!metadata.is_object()) return nullptr;
  if (const auto it = metadata.find("tile"); it != metadata.end() && it->is_object()) return &*it;
  const auto history = metadata.find("history");
  if (history == metadata.end() || !history->is_array()) return nullptr;
  for (auto it = history->rbegin(); it != history->rend(); ++it)
    if (it->is_object())
      if (const auto tile = it->find("tile"); tile != it->end() && tile->is_object()) return &*tile;
  return nullptr;
}

}  // namespace

std::optional<Bounds> tile_survey_box(const nlohmann::json& metadata,
                                      const std::array<double, 3>& origin, const Bounds& own) {
  const nlohmann::json* tile = find_tile(metadata);
  if (tile == nullptr || !tile->contains("survey_box")) return std::nullopt;
  try {
    const nlohmann::json& box = tile->at("survey_box");
    Bounds b;
    for (int a = 0; a < 3; ++a) {
      const double lo = box.at("min").at(a).get<double>(), hi = box.at("max").at(a).get<double>();
      if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) return std::nullopt;
      // (the tile's positions are float32 values p with origin + p exact in float64)
      b.min[a] = static_cast<float>(lo - origin[static_cast<std::size_t>(a)]);
      b.max[a] = static_cast<float>(hi - origin[static_cast<std::size_t>(a)]);
      if (!std::isfinite(b.min[a]) || !std::isfinite(b.max[a]) || !(b.min[a] <= own.min[a]) ||
          !(own.max[a] <= b.max[a]))
        return std::nullopt;
    }
    return b;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

}  // namespace splatkit::apps
