// Reading any supported point-cloud file into a SplatCloud.
//
// The format is detected from the content first (magic bytes: "ply", "# .PCD"/"VERSION",
// "LASF", "OFF", the .splk magic), the extension second (.xyz .pts .txt .csv), so that "-"
// (stdin) works for every format. Every reader treats its input as hostile: sizes and counts are
// checked against the bytes available, NaN/Inf coordinates are rejected, trailing garbage is an
// error; failures throw Error(kBadInput) naming the file and where, or Error(kUnsupported)
// (LAZ, unknown major versions).
#pragma once

#include <string>
#include <string_view>

#include "formats/loaded_cloud.h"
#include "splatkit/input_stream.h"

namespace splatkit {

enum class FileFormat { kUnknown, kPly, kXyz, kPcd, kOff, kLas, kLaz, kSplk };

std::string_view format_name(FileFormat f);

struct ReadOptions {
  // XYZ/CSV/PTS/TXT: column layout such as "x,y,z,nx,ny,nz,r,g,b" ('_' skips a column); empty =
  // detect from the header line or the column count.
  std::string columns;
  // Format to assume when neither the content nor the name tells (e.g. "xyz" for a pipe).
  FileFormat assume = FileFormat::kUnknown;
};

// Looks at the first bytes of `in` (without consuming them) and at `path`'s extension.
FileFormat detect_format(InputStream& in, const std::string& path);

LoadedCloud read_cloud(const std::string& path, const ReadOptions& options = {});
LoadedCloud read_cloud(InputStream& in, const ReadOptions& options = {});

}  // namespace splatkit
