// Reading any supported point-cloud file into a SplatCloud.
//
// The format is detected from the content first (magic bytes: "ply", "# .PCD"/"VERSION",
// "LASF", "OFF", the .splk magic), the extension second (.xyz .pts .txt .csv), and last from the
// content again: text lines of numbers are XYZ, as is any input when ReadOptions::columns is
// given, so that "-" (stdin) works for every format. An empty input (0 bytes) is bad input; a
// well-formed file without points gives an empty cloud. Every reader treats its input as hostile:
// sizes and counts are checked against the bytes available, NaN/Inf coordinates and values beyond
// float range are rejected, trailing garbage is an error; failures throw Error(kBadInput) naming
// the file and where, or Error(kUnsupported) (LAZ, unknown major versions).
#pragma once

#include <string>
#include <string_view>

#include "formats/loaded_cloud.h"
#include "splatkit/input_stream.h"
#include "splatkit/progress.h"

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

// True when `head` (the first bytes of an input; `complete` when it is the whole input) reads as
// delimited text columns: printable text whose first line that is not blank, a '#' comment, a
// header of names or a PTS count holds at least 3 numbers.
bool looks_like_text_columns(std::string_view head, bool complete);

// `progress` sees the fraction of the file read (or, on a pipe, a negative fraction and the bytes
// read so far; see InputStream::set_progress), ending with 1 when the cloud is loaded. It may
// throw Cancelled to stop the read; nothing is returned then.
LoadedCloud read_cloud(const std::string& path, const ReadOptions& options = {},
                       const ProgressFn& progress = no_progress());
LoadedCloud read_cloud(InputStream& in, const ReadOptions& options = {},
                       const ProgressFn& progress = no_progress());

}  // namespace splatkit
