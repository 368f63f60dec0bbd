// drop_halo_points: a tile of splat-tile reduced to its own points, in place (formats/tiles.md),
// for the tools that build one file per tile (build-spt, build-qsplat: a tile's level-of-detail
// file holds only its own points, so that the tiles' files together hold each point once).
#pragma once

#include <cstddef>
#include <string>

#include "splatkit/splat_cloud.h"

namespace splatkit {

// Removes the points whose `halo` attribute is 1, and the attribute (take_own_points.h); a cloud
// without it is left as it is. Keeps every per-point array of the rest in order; faces are not
// kept when points go (tiles have none). Returns the number of points removed. `name` names the
// cloud in errors.
std::size_t drop_halo_points(SplatCloud& cloud, const std::string& name);

}  // namespace splatkit
