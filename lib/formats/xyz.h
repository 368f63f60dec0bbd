// Delimited text point clouds: XYZ / PTS / TXT / CSV. Spec: formats/xyz.md.
#pragma once

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

// Whitespace- or comma-separated columns, optional header line (names or a PTS point count),
// '#' comments. Column meaning from options.columns, else the header names, else the count:
// 3 = xyz, 4 = xyz+intensity (PTS), 6 = xyz+normal (or xyz+rgb when all three are integers 0-255),
// 7 = xyz+intensity+rgb (PTS), 9 = xyz+normal+rgb.
LoadedCloud read_xyz(InputStream& in, const ReadOptions& options = {});

// Shortest round-tripping decimals separated by `separator`: ' ' under a header comment line
// naming the columns ("# x y z ..."), ',' (CSV) under a header line of the names ("x,y,z,...").
void write_xyz(const SplatCloud& cloud, OutputFile& out, char separator = ' ');

}  // namespace splatkit
