// tile_walls: where a tile of splat-tile meets its neighbours, the walls estimate-normals' views
// do not look through.
#pragma once

#include <nlohmann/json.hpp>

#include <vector>

#include "normals/visibility_votes.h"
#include "splatkit/splat_cloud.h"

namespace splatkit::apps {

// From a tile's metadata (formats/tiles.md: "tile" with "square", "halo" and "skyline": per side
// the heights of the survey's highest points just beyond it, by segment), in `cloud`'s local
// frame: per segment of a side that the survey reaches beyond, a wall on the outer edge of the
// halo from the cloud's lowest point up to that height. Beyond such a border the survey goes on
// and hides from the views what a view through the cut would see: the inner faces of a building
// or a part cut in two. Empty when the metadata holds no tile or no skyline; metadata that does
// not read as that (a hand-edited or hostile file) gives no walls: it never fails a run.
std::vector<VisibilityWall> tile_walls(const nlohmann::json& metadata, const SplatCloud& cloud);

}  // namespace splatkit::apps
