// Heightmaps without a header: SRTM .hgt tiles (square, big-endian int16, -32768 = void, the side
// from the file's length: 1201 for 3 arc-seconds, 3601 for 1 arc-second) and headerless RAW files
// described on the command line (--raw W,H,TYPE[,ENDIAN]). Both are read sequentially, so RAW may
// come from standard input ("-").
#pragma once

#include <memory>
#include <string>

#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

struct RawLayout {
  int64_t width = 0, height = 0;
  std::string type = "float32";  // int8 uint8 int16 uint16 int32 uint32 float32 float64
  bool big_endian = false;
};

// Parses "W,H,TYPE[,ENDIAN]" (ENDIAN: little or big, default little). Throws Error(kUsage).
RawLayout parse_raw_layout(const std::string& text);

// Throws Error(kBadInput) naming the file when its length is not width × height × sample size
// (a regular file; standard input is checked as it is read).
std::unique_ptr<HeightmapSource> open_raw_heightmap(const std::string& path,
                                                    const RawLayout& layout);

// Throws Error(kBadInput) when the length is not 2·N² for some N ≥ 2. The name's SW corner
// (N27E086.hgt) becomes the georeferencing when it parses.
std::unique_ptr<HeightmapSource> open_hgt(const std::string& path);

}  // namespace splatkit::terrain
