// Writing a SplatCloud: binary PLY, ASCII PLY, XYZ text, OFF, LAS/LAZ, or .splk.
#pragma once

#include <string>
#include <vector>

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

struct WriteOptions {
  FileFormat format = FileFormat::kUnknown;  // kUnknown = from the extension; "-" => .splk
  bool ascii = false;                        // PLY: ascii instead of binary_little_endian
  bool big_endian = false;                   // PLY: binary_big_endian
  // LAS/LAZ point data format: 0-3 or 6-8 (LAS 1.4), or -1: the source's when it was LAS/LAZ of
  // format 6-8 (6, 7 with colours, 8 with colours and NIR), else 0-3 by the cloud's fields.
  int las_format = -1;
};

// Format for an output path: by extension; "-" and unknown extensions give .splk.
FileFormat output_format_for(const std::string& path);
// The format an output path's extension names (any case), or kUnknown (none, or one that names
// no format).
FileFormat format_of_extension(const std::string& path);
// The format write_cloud writes `path` in with `options`; throws Error(kUnsupported) for one it
// cannot write (PCD). For checking an output before the work.
FileFormat writable_format(const std::string& path, const WriteOptions& options);

// What `doc` holds that writing it as `format` (a writable one; `options` for LAS's point format)
// leaves out, in words: e.g. {"normals", "radii", "attribute surface_id", "chunk SURF"}. Empty
// when the format keeps everything.
std::vector<std::string> fields_not_written(const LoadedCloud& doc, FileFormat format,
                                            const WriteOptions& options = {});

// Writes `doc` (its cloud; for .splk also its metadata and carried chunks) through an atomic
// OutputFile and commits it. Throws Error(kOutput) or Error(kUnsupported) (e.g. PCD output).
void write_cloud(const LoadedCloud& doc, const std::string& path, const WriteOptions& options = {});
// The same into `out` without committing it (format from options.format, else out's path), so
// that a caller can finish other outputs before it commits this one.
void write_cloud(const LoadedCloud& doc, OutputFile& out, const WriteOptions& options = {});

}  // namespace splatkit
