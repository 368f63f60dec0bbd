// check_tile_halo: does a tile's halo hold the neighbourhoods of its own points?
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>

#include "splatkit/splat_cloud.h"

namespace splatkit::apps {

struct TileHaloCheck {
  bool tile = false;           // the metadata names a tile of splat-tile (else nothing was checked)
  double halo = 0;             // the tile's halo
  std::size_t checked = 0;     // own points near a side beyond which the survey goes on
  std::size_t short_of = 0;    // of them, those whose neighbourhoods reach past the halo
  double needed = 0;           // the halo that would hold every checked point's (0: the halo does)
  nlohmann::json to_json() const;
};

// The neighbourhoods estimate-normals reads for a point reach as far as its 64 nearest points'
// own 32-rows (the refit's 64-row, each member with its own 32-row), at most twice the distance to
// its 64th nearest where the density is even: the rule splat-tile's default halo follows
// (tile_halo.h). That bound screens the points; those it does not pass are measured. A tile's results equal a run over the whole survey where
// that reach stays within what the tile holds: its own square widened by the halo on the sides
// beyond which the survey goes on (the skyline says where it does). Checks the own points
// (halo attribute 0) within one halo of such a side: deeper points would need a 64th nearest
// point farther than a halo, which on the default halo is twice the 99th percentile of that
// distance (and where it is so, their shallower neighbours are short too). Positions in
// `cloud`'s local frame, its origin added back. Nothing is checked when the metadata holds no
// tile.
TileHaloCheck check_tile_halo(const nlohmann::json& metadata, const SplatCloud& cloud);

}  // namespace splatkit::apps
