// Writing LAS 1.2 (point data formats 0-3), LAS 1.4 (formats 6-8) and LAZ (LASzip point-wise
// chunked for 0-3, layered chunked for 6-8). Spec: formats/las.md (writer section) and
// formats/laz.md.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "formats/loaded_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

struct LasRecordsLayout {
  int format = 0;              // point data format 0-3 or 6-8
  uint16_t record_length = 20; // at least the format's size; the rest are extra bytes
  double scale[3] = {0.001, 0.001, 0.001};
  double offset[3] = {0, 0, 0};
  std::string generating_software = "splatkit";
  // File creation day of year (1-366) and year: las_creation_date() by default.
  uint16_t creation_day = 0, creation_year = 0;
};

// The creation date splatkit writes, the same on every run so that outputs stay byte-identical:
// the UTC date of $SOURCE_DATE_EPOCH (seconds since 1970, the reproducible-builds convention) when
// it is set to such a number, else day 1 of 2000. Returns {day of year, year}.
std::pair<uint16_t, uint16_t> las_creation_date();

// Writes `count` LAS records (record_length bytes each, as in an uncompressed file) as a LAS 1.2
// file (formats 0-3) or LAS 1.4 file (formats 6-8, 64-bit point counts), or, when `compressed`,
// as LAZ with chunks of `chunk_size` points. The creation date is the layout's, or
// las_creation_date() when its year is 0. The header's bounds and returns-by-number counts are
// computed from the records. Throws Error(kUnsupported) for more than 2^32 - 1 points in LAS 1.2.
// variable_chunks: the LASzip VLR says "variable" and the chunk table stores each chunk's point
// count (chunks then hold chunk_size, chunk_size + 1, chunk_size + 2,
// ... points, to exercise it).
void write_las_records(OutputFile& out, const LasRecordsLayout& layout, const unsigned char* records,
                       uint64_t count, bool compressed, uint32_t chunk_size = 50000,
                       bool variable_chunks = false);

// Writes a cloud as LAS/LAZ: point data format `las_format` (0-3, 6-8), or when -1 the source's
// when it was LAS/LAZ of format 6-8 (7 and 8 only with colours), else 0-3 by what the cloud has
// (RGB: 2/3, gps_time: 1/3);
// the LAS extras the LAS reader makes (intensity, return numbers, classification, scan_angle,
// user_data, point_source_id, gps_time) go back to their fields. Scale and offset are the source
// file's when it was LAS/LAZ, else 0.001 (coarser when the extent needs it) and the cloud's origin.
void write_las(const LoadedCloud& doc, OutputFile& out, bool compressed, int las_format = -1);
// The point data format write_las writes `doc` in for `las_format` (-1: chosen as above).
int las_output_format(const LoadedCloud& doc, int las_format);
// The names of the cloud attributes (extras) that a LAS record of point data `format` holds.
std::vector<std::string> las_kept_attributes(int format);

}  // namespace splatkit
