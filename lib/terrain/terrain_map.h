// A heightmap held in memory for viewing: read with the build-ham readers, voids filled the same
// way (fill_voids.h), heights multiplied by z_scale, sampled bilinearly at texel coordinates, with
// its own normals (central differences of those samples) for per-pixel shading.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "splatkit/vec3.h"
#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

struct TerrainMap {
  int64_t width = 0, height = 0;
  std::vector<float> heights;  // row-major, filled and scaled
  float h_min = 0, h_max = 0;

  float at(int64_t x, int64_t y) const { return heights[std::size_t(y * width + x)]; }
  // Bilinear at texel coordinates, clamped to the map.
  double sample(double x, double y) const;
  // The unit normal at texel coordinates (x, y) in the view's frame (x east, y north, z up; a
  // texel is sx by sy metres, heights as stored): central differences of sample() one texel
  // either side, (-dh/dx / sx, dh/dy / sy, 1) normalised (texel rows run south, hence the sign).
  // Between texels this is the bilinear blend of the texels' central differences; at a texel it
  // is the texel's own. Within a texel of the border the step shrinks to the samples the map
  // holds (one-sided on the border), so a plane's normal is exact everywhere.
  Vec3f normal(double x, double y, double sx, double sy) const;
};

// Opens `path` as build-ham does (.hgt, RAW with `raw` = "W,H,TYPE[,ENDIAN]", else the image
// module). Throws as the readers do; Error(kOutOfMemory) beyond memory.
std::unique_ptr<HeightmapSource> open_heightmap(const std::string& path, const std::string& raw);

TerrainMap load_terrain_map(HeightmapSource& source, std::optional<double> nodata,
                            double z_scale);

}  // namespace splatkit::terrain
