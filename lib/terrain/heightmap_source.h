// A heightmap read row by row, top row first: the one interface behind every heightmap reader
// (raw_heightmap.h for SRTM .hgt and headerless RAW, terrain_images.h for TIFF/PNG/EXR through
// OpenImageIO), so that build-ham streams any of them in bands of rows and never holds the whole
// map.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace splatkit::terrain {

struct HeightmapInfo {
  int64_t width = 0, height = 0;
  std::string format;        // "tiff", "png", "exr", "hgt", "raw", ...
  std::string sample_type;   // "int16", "float32", ...
  bool has_nodata = false;   // the file's own no-data value (GDAL_NODATA tag, SRTM's -32768)
  double nodata = 0;
  int64_t band_rows = 64;    // rows the reader prefers per call (a TIFF's tile or strip height)
  nlohmann::json georef;     // georeferencing kept from the file (null when it has none)
};

class HeightmapSource {
 public:
  virtual ~HeightmapSource() = default;
  const HeightmapInfo& info() const { return info_; }
  // Reads the next `rows` rows (width floats each) into `out`, in elevation units as stored
  // (integers are not normalised). Throws Error(kBadInput) naming the file on a short or
  // unreadable file.
  virtual void read_rows(int64_t rows, float* out) = 0;

 protected:
  HeightmapInfo info_;
};

}  // namespace splatkit::terrain
