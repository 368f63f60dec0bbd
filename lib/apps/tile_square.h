// tile_square: the square, halo and skyline that splat-tile records in a tile's metadata
// (formats/tiles.md), read defensively.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>

namespace splatkit::apps {

struct TileSquare {
  double lo[2] = {0, 0}, hi[2] = {0, 0};  // the tile's own square in plan, file coordinates
  double halo = 0;                        // how far beyond it the file holds the survey's points
  const nlohmann::json* skyline = nullptr;  // the metadata's "skyline", or null
};

// The tile in `metadata` (its "tile" object), or nothing when the metadata holds none or does
// not read as one (a hand-edited or hostile file): callers then treat the cloud as a whole
// survey. The skyline pointer refers into `metadata`.
std::optional<TileSquare> tile_square(const nlohmann::json& metadata);

// Whether the survey goes on beyond side s of the tile (0: -x, 1: +x, 2: -y, 3: +y), as its
// skyline says (some segment holds a height); true when the tile records no skyline.
bool survey_goes_on(const TileSquare& tile, int side);

// The skyline's side names, in the order of survey_goes_on's sides.
inline constexpr const char* kTileSides[4] = {"-x", "+x", "-y", "+y"};

}  // namespace splatkit::apps
