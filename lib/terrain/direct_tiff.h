// Uncompressed single-band TIFF heightmaps (8/16/32/64-bit integer or float, stripped or tiled,
// either byte order) read straight from the file with pread, without OpenImageIO: the common
// case of elevation data, and a run that loads no image library at all. Every strip or tile is
// checked to lie inside the file before any row is read.
#pragma once

#include <memory>
#include <string>

#include "terrain/heightmap_source.h"
#include "terrain/tiff_geo_tags.h"

namespace splatkit::terrain {

// Null when the layout is not one this reader takes (compressed, several samples, odd bit
// depths): the caller falls back to OpenImageIO. Throws Error(kBadInput) naming the file when the
// layout is inconsistent (strips or tiles missing, or past the end of the file).
std::unique_ptr<HeightmapSource> open_direct_tiff(const std::string& path, const TiffGeoTags& tags);

}  // namespace splatkit::terrain
