// splat-info for the terrain files: a heightmap that build-ham reads (TIFF/GeoTIFF, PNG, EXR,
// SRTM .hgt) or build-ham's per-tile HAM EXR.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace splatkit::apps {

// The report of `path` when its extension names a heightmap or tile format (.tif .tiff .png .exr
// .hgt, any case), else null. A tile EXR gives "format": "ham" (map and tile sizes, z scale,
// height range, largest HAM, voids, georeferencing); any other heightmap "format": "heightmap"
// (size, sample type, no-data, georeferencing), reading every sample once for the height range;
// both with the keys every report has (formats/describe_common.h: "points" the samples of a
// heightmap, "entries" the tiles of a tile EXR). Throws as the readers do.
nlohmann::json describe_terrain_file(const std::string& path);

// The text splat-info prints for such a report.
std::string describe_terrain_text(const nlohmann::json& report);

// What `path` is by its first bytes when it is a file splatkit reads as something other than a
// heightmap ("a QSplat hierarchy (.qs)", "a PLY file", ...), else "" (also for '-', unreadable
// files and anything else: the heightmap readers then say what is wrong).
std::string non_heightmap_kind(const std::string& path);

// Throws Error(kUnsupported) "<path>: <kind>, not a heightmap: ..." when non_heightmap_kind says
// so (build-ham's input, splat-view --terrain's map).
void check_heightmap_kind(const std::string& path);

}  // namespace splatkit::apps
