// LAZ (LASzip-compressed LAS) point data: point data formats 0-3 (point-wise chunked compressor,
// version 2 items) and 6-8 (layered chunked compressor, version 3 items). Spec: formats/laz.md.
// read_las calls read_laz_points for a file whose point format byte has the compression bit; the
// header and VLRs are LAS's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "splatkit/input_stream.h"

namespace splatkit {

struct LazPointsInfo {
  int format = 0;                             // point data format (low 6 bits of the format byte)
  uint16_t record_length = 0;                 // bytes per decoded record
  uint64_t count = 0;                         // points the header announces
  uint64_t point_offset = 0;                  // file offset of the point data (where `in` stands)
  std::span<const unsigned char> laszip_vlr;  // payload of the LASzip VLR; empty when absent
  bool has_laszip_vlr = false;
  uint64_t evlr_start = 0;  // LAS 1.4: file offset of the first extended VLR
  uint32_t evlr_count = 0;  // and how many there are (they follow the chunk table)
};

// Checks the LASzip VLR against the format (Error kUnsupported for a compressor, coder, item or
// version this decoder lacks, kBadInput for an inconsistent one). Call before reading points.
void check_laz_vlr(const std::string& path, const LazPointsInfo& info);

// Reads the rest of `in` (point data, chunk table, anything after) and passes the decoded records
// to `sink` in file order, record_length bytes each, in batches of whole chunks; the chunks are
// decoded in parallel (a TBB pipeline: later chunks are decoded while `sink` takes earlier ones;
// `sink` is called by one thread at a time, not always the caller's). Throws Error(kBadInput) naming the chunk for a truncated or
// corrupt chunk, a chunk table that does not fit the file, a point count the chunks disagree
// with, or bytes after the chunk table (or after the last EVLR) that belong to nothing, as LAS.
void read_laz_points(InputStream& in, const LazPointsInfo& info,
                     const std::function<void(const unsigned char* records, std::size_t n)>& sink);

}  // namespace splatkit
