// A heightmap held in memory for viewing: read with the build-ham readers, voids filled the same
// way (fill_voids.h), heights multiplied by z_scale, sampled bilinearly at texel coordinates.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

struct TerrainMap {
  int64_t width = 0, height = 0;
  std::vector<float> heights;  // row-major, filled and scaled
  float h_min = 0, h_max = 0;

  float at(int64_t x, int64_t y) const { return heights[std::size_t(y * width + x)]; }
  // Bilinear at texel coordinates, clamped to the map.
  double sample(double x, double y) const;
};

// Opens `path` as build-ham does (.hgt, RAW with `raw` = "W,H,TYPE[,ENDIAN]", else the image
// module). Throws as the readers do; Error(kOutOfMemory) beyond memory.
std::unique_ptr<HeightmapSource> open_heightmap(const std::string& path, const std::string& raw);

TerrainMap load_terrain_map(HeightmapSource& source, std::optional<double> nodata,
                            double z_scale);

}  // namespace splatkit::terrain
