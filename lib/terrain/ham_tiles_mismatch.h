// Whether build-ham's tiles describe a heightmap: each tile's largest height (filled and scaled
// as build-ham does, with the z scale and no-data value the tiles record) must be the tile's
// h_max, up to float rounding. Tiles of another map of the same size differ there.
#pragma once

#include <string>

#include "terrain/ham_tiles.h"
#include "terrain/terrain_map.h"

namespace splatkit::terrain {

// Empty when they match (and when the sizes differ: the caller reports that), else the first tile
// that does not, in row-major order, with both heights.
std::string ham_tiles_mismatch(const TerrainMap& map, const HamTiles& tiles);

}  // namespace splatkit::terrain
