// Void filling for streamed heightmaps: a no-data run inside a row is replaced by the straight
// line between the valid samples on either side (or the nearer one's value at the row's ends),
// so a filled sample never lies outside the heights around it and a void never becomes a cliff
// in the derivatives that follow. A row with no valid sample copies the filled row above it (or,
// for the first rows of the map, the first row that has valid samples). Rows are filled one at a
// time: memory does not depend on the map's size.
#pragma once

#include <cstdint>

namespace splatkit::terrain {

// Whether `v` is a void: not finite, or equal to `nodata` when has_nodata.
inline bool is_void(float v, bool has_nodata, float nodata) {
  return !(v - v == 0.0f) || (has_nodata && v == nodata);
}

// Fills the voids of one row of `width` samples in place; returns how many there were, or
// `width` (nothing changed) when the row has no valid sample.
int64_t fill_row_voids(float* row, int64_t width, bool has_nodata, float nodata);

}  // namespace splatkit::terrain
