// common_origin: the one frame for files of several tiles (merged level-of-detail files), whose
// origins splat-tile chooses per tile: the survey's for most, a tile's own far from it
// (formats/tiles.md).
#pragma once

#include <array>
#include <span>

namespace splatkit {

// The origin most of `origins` share, ties broken by the smallest (lexicographically), so that
// the choice does not depend on their order. Precondition: not empty.
std::array<double, 3> common_origin(std::span<const std::array<double, 3>> origins);

}  // namespace splatkit
