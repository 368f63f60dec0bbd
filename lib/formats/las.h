// ASPRS LAS 1.0–1.4, point data formats 0–3 (any version) and 6–8 (LAS 1.4); LAZ (LASzip) for
// formats 0–3 through formats/laz.h. Spec: formats/las.md, formats/laz.md.
#pragma once

#include <cstdint>
#include <functional>

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"

namespace splatkit {

// Applies scale and offset (coordinates kept in float64 until the origin is chosen), keeps 16-bit
// RGB (color_bits = 16), intensity/classification/return numbers/gps_time as extras. LAZ files
// (bit 7 of the point format byte) are decompressed; LAZ variants it lacks throw
// Error(kUnsupported).
LoadedCloud read_las(InputStream& in, const ReadOptions& options = {});

// The point records of a LAS or LAZ file as an uncompressed file holds them (LAZ decompressed),
// passed to `sink` in file order in blocks; same checks and errors as read_las.
struct LasRecordsInfo {
  int format = 0;
  uint16_t record_length = 0;
  uint64_t count = 0;
  bool compressed = false;
};
// `on_info` runs once the header is read, before the first records.
LasRecordsInfo read_las_records(
    InputStream& in, const std::function<void(const unsigned char* records, std::size_t n)>& sink,
    const std::function<void(const LasRecordsInfo&)>& on_info = {});

}  // namespace splatkit
