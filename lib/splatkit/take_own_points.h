// take_own_points: a tile's own points, without its halo (splat-tile, formats/tiles.md).
#pragma once

#include <cstdint>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

// The uint8 attribute with which splat-tile marks a tile's halo points (1; its own points 0).
inline constexpr const char* kHaloAttribute = "halo";

// The indices of cloud's points whose `halo` attribute is 0 (all of them when it has none), in
// ascending order; the attribute is removed from the cloud.
std::vector<uint32_t> take_own_points(SplatCloud& cloud);

}  // namespace splatkit
