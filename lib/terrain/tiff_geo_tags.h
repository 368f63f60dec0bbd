// The TIFF tags OpenImageIO drops: GDAL's no-data value (tag 42113) and the GeoTIFF
// georeferencing (ModelPixelScale 33550, ModelTiepoint 33922, ModelTransformation 34264,
// GeoKeyDirectory 34735), read from the first image directory of a classic or BigTIFF file.
// Bounds-checked, linear in the directory's size; reads only the bytes it needs through `read`.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace splatkit::terrain {

// The layout of the first image, for reading uncompressed single-band files directly.
struct TiffLayout {
  bool little_endian = true;
  uint64_t width = 0, height = 0;
  uint64_t bits = 0, sample_format = 1, samples = 1, compression = 1, planar = 1;
  uint64_t rows_per_strip = 0, tile_width = 0, tile_height = 0;
  std::vector<uint64_t> offsets, byte_counts;  // strips or tiles
};

struct TiffGeoTags {
  std::optional<double> nodata;
  nlohmann::json georef;  // null when the file has no GeoTIFF tags
  TiffLayout layout;
};

// Reads n bytes at offset into out; false when the file is shorter.
using ReadAt = std::function<bool(uint64_t offset, std::size_t n, void* out)>;

// Throws Error(kBadInput) naming `name` for a malformed header or directory (offsets outside the
// file, a directory of more than 65535 entries, a tag value that does not parse).
TiffGeoTags read_tiff_geo_tags(const ReadAt& read, const std::string& name);

// The same on a file (pread) or a memory buffer (for the fuzzer).
TiffGeoTags read_tiff_geo_tags_file(const std::string& path);
TiffGeoTags read_tiff_geo_tags_memory(const uint8_t* data, std::size_t size,
                                      const std::string& name);

}  // namespace splatkit::terrain
