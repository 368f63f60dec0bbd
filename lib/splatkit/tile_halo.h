// tile_halo: the halo splat-tile gives each tile when none is asked for.
#pragma once

#include <span>

#include "splatkit/vec3.h"

namespace splatkit {

// The widest neighbourhood estimate-normals reads for a point with its defaults: the refit of a
// splat reads the 64 nearest points (4 rows of k = 16) and the final normal of each, which comes
// from that neighbour's own row of up to 32 points (2k where its k-row shows no plane).
inline constexpr std::size_t kTileHaloRow = 64;
inline constexpr double kTileHaloQuantile = 0.99;
inline constexpr std::size_t kTileHaloSample = 20000;

// The halo (same units as `positions`) that holds the neighbourhoods of kTileHaloRow points of
// almost every point: twice the kTileHaloQuantile quantile of the distance from a point to its
// kTileHaloRow-th nearest, over an even sample of at most kTileHaloSample of the points (the
// neighbourhood a point's result depends on reaches that row's last point and that point's own
// row, each at most that distance where the density is even). 0 for fewer than kTileHaloRow
// points. Deterministic.
double tile_halo(std::span<const Vec3f> positions);

}  // namespace splatkit
