// The part of splat-info's report that every kind of file shares, so that a point cloud, a
// QSplat .qs, a Sequential Point Tree .spt, a heightmap and build-ham's tiles are described with
// the same keys and the same first lines:
//
//   "file"     the name as given ("-" for standard input)
//   "format"   short name: "ply", "las", "laz", "splk", "qs", "spt", "heightmap", "ham", ...
//   "bytes"    the file's size (absent only for a stream whose size is unknown)
//   "points"   point clouds and heightmaps (samples): the points the file holds, or
//   "entries"  .qs (tree nodes), .spt (list entries), tile EXRs (tiles)
//   "bounds"   {"min": [x, y, z], "max": [x, y, z]} in the file's coordinates (a local origin
//              added back); a component that is not known is null; absent for an empty cloud
//   "crs"      the coordinate reference system ("EPSG:4326", ...), null when none is recorded
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace splatkit {

// Rounds every floating-point number of `report` (recursively) to what its source could hold:
// a value that is exactly a float32 to the shortest text that reads back as that float32, any
// other to 12 significant digits (a UTM coordinate to the micrometre). No report prints 17 digits.
void tidy_report_numbers(nlohmann::json& report);

// The double nearest the shortest decimal text that reads back as `f` (0.1f -> 0.1, not
// 0.100000001490116): the float32 part of a coordinate before a float64 origin is added to it.
double shortest_value(float f);

// The first lines of the text report, the same for every kind:
//   File: F / Format: FORMAT_LINE / Bytes: N / Points: N or Entries: N (DETAIL) /
//   Bounds: min (x, y, z) / max (x, y, z) / CRS: C or none
// `count_detail`, when not empty, follows the count in parentheses.
std::string describe_common_text(const nlohmann::json& report, const std::string& format_line,
                                 const std::string& count_detail = "");

// A number as the text report prints it: integers without ".0", others as the tidied JSON holds
// them; null as "?".
std::string report_number(const nlohmann::json& v);

}  // namespace splatkit
