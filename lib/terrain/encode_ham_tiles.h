// The per-tile HAM EXR (formats/ham.md) encoded with OpenEXR itself: a handful of small shared
// libraries instead of OpenImageIO's hundreds, so that build-ham on an uncompressed TIFF, .hgt or
// RAW input loads no image library beyond it. Deterministic: the same tiles give the same bytes.
#pragma once

#include <vector>

#include "terrain/ham_tiles.h"

namespace splatkit::terrain {

// Throws Error(kInternal) if OpenEXR fails (it writes to memory).
std::vector<unsigned char> encode_ham_tiles(const HamTiles& tiles);

}  // namespace splatkit::terrain
