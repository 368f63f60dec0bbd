// What a reader returns: the cloud plus what the file said about itself.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

// The most attributes (PLY properties of an element, PLY elements, text columns, .splk columns) a
// reader accepts. Real files have tens; each one costs the reader and splat-info far more memory
// than the few header bytes that declare it, so a header of millions would take gigabytes.
inline constexpr std::size_t kMaxAttributes = 16384;

// A .splk chunk that splatkit does not decode here: kept byte for byte and written back.
struct RawChunk {
  char type[4] = {0, 0, 0, 0};
  uint32_t flags = 0;
  std::vector<unsigned char> payload;
};

struct LoadedCloud {
  SplatCloud cloud;
  std::string format;  // "ply", "xyz", "pcd", "off", "las", "splk"
  // Format-specific facts shown by splat-info, e.g. {"encoding": "binary_little_endian",
  // "elements": [...]} for PLY or {"version": "1.4", "point_format": 6, "scale": [...]} for LAS.
  nlohmann::json header = nlohmann::json::object();
  // .splk only: the metadata chunk and the chunks this reader did not decode (carried through).
  nlohmann::json metadata = nlohmann::json::object();
  std::vector<RawChunk> chunks;
};

}  // namespace splatkit
