// tile_survey_box: the box of the whole survey that splat-tile records in each tile's metadata
// (formats/tiles.md, "survey_box"), read defensively and moved into a cloud's frame, so that
// build-spt can build a tile's octree in the survey's Morton cube (spt/build_spt_tree.h).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <optional>

#include "splatkit/splat_cloud.h"

namespace splatkit::apps {

// The survey box of the tile in `metadata`: its "tile" object, else that of the newest entry of
// "history" holding one (a tile passed through estimate-normals), in the frame of `origin` (file
// coordinates minus origin, as float32). Nothing when no tile records a box or the box does not
// read as one (not numbers, not finite in float32 in that frame, min > max: a hand-edited or
// hostile file) or does not hold `own` (the tile's own points' box, in the same frame): callers
// then use the points' own box, as for a whole survey.
std::optional<Bounds> tile_survey_box(const nlohmann::json& metadata,
                                      const std::array<double, 3>& origin, const Bounds& own);

}  // namespace splatkit::apps
