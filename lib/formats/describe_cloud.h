// What splat-info reports about a file: format, counts, attributes with ranges, bounding box,
// the format's own header facts, and for .splk its chunks and metadata.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "formats/loaded_cloud.h"

namespace splatkit {

// JSON report with the keys every report has (formats/describe_common.h; "crs" null: no reader
// keeps a cloud's CRS yet), then "faces", "attributes", "origin", "header", "metadata". Bounding box and origin are in file
// coordinates (origin added back). `file_bytes` is included when known.
nlohmann::json describe_cloud(const LoadedCloud& doc, const std::string& path,
                              std::optional<uint64_t> file_bytes);

// The same report as human-readable text (gdalinfo style).
std::string describe_cloud_text(const nlohmann::json& report);

}  // namespace splatkit
