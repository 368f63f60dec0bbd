// The per-tile summary of a height acceleration map (HAM) that drives terrain tessellation: one
// record per tile of tile × tile texels (the last row and column of tiles may be partial), row
// by row. Stored as an EXR image of tiles_x × tiles_y pixels with the named channels ham_max,
// h_max (float) and x, y, voids (uint32) and the header attributes of `header` (formats/ham.md).
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace splatkit::terrain {

struct HamTiles {
  int64_t width = 0, height = 0;  // the heightmap's size, texels
  int64_t tile = 64;              // tile side, texels
  int64_t tiles_x = 0, tiles_y = 0;
  double z_scale = 1;             // heights (h_max) are the file's values times z_scale
  std::vector<float> ham_max;     // largest HAM value in the tile
  std::vector<float> h_max;       // largest (filled, scaled) height in the tile
  std::vector<uint32_t> x, y;     // texel of h_max in the heightmap, first in row-major order
  std::vector<uint32_t> voids;    // no-data texels filled in the tile
  nlohmann::json header = nlohmann::json::object();  // georef, nodata, h_min, texel size, ...

  void resize(int64_t w, int64_t h, int64_t t) {
    width = w;
    height = h;
    tile = t;
    tiles_x = (w + t - 1) / t;
    tiles_y = (h + t - 1) / t;
    const std::size_t n = std::size_t(tiles_x * tiles_y);
    ham_max.assign(n, 0.0f);
    h_max.assign(n, -INFINITY);
    x.assign(n, 0);
    y.assign(n, 0);
    voids.assign(n, 0);
  }
  std::size_t size() const { return ham_max.size(); }
};

}  // namespace splatkit::terrain
