// Shared by the terrain tests: a heightmap source over rows in memory, and a map with its HAM
// tiles and frame.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>
#include <vector>

#include "terrain/compute_ham.h"
#include "terrain/terrain_map.h"
#include "terrain/tess_factors.h"

namespace splatkit::terrain::test {

// Rows of `data` (w x h, row-major), served band by band.
class MemorySource final : public HeightmapSource {
 public:
  MemorySource(std::vector<float> data, int64_t w, int64_t h, int64_t band_rows = 64)
      : data_(std::move(data)) {
    info_.width = w;
    info_.height = h;
    info_.band_rows = band_rows;
  }
  void read_rows(int64_t rows, float* out) override {
    std::memcpy(out, data_.data() + next_ * info_.width, std::size_t(rows * info_.width) * 4);
    next_ += rows;
  }
  void set_nodata(float v) {
    info_.has_nodata = true;
    info_.nodata = v;
  }

 private:
  std::vector<float> data_;
  int64_t next_ = 0;
};

struct Terrain {
  TerrainMap map;
  HamTiles tiles;
  TerrainFrame frame;
};

// The map of `heights` (w x h, row-major), its HAM tiles of `tile` texels and a frame of square
// texels `sx` metres wide.
inline Terrain make_terrain(const std::vector<float>& heights, int64_t w, int64_t h, int64_t tile,
                            double sx) {
  Terrain t;
  MemorySource a(heights, w, h), b(heights, w, h);
  HamOptions o;
  o.tile = tile;
  HamStats stats;
  t.tiles = compute_ham(a, o, stats);
  t.map = load_terrain_map(b, std::nullopt, 1.0);
  t.frame.sx = t.frame.sy = sx;
  t.frame.h_min = t.map.h_min;
  t.frame.ham_ref = stats.ham_max;
  return t;
}

}  // namespace splatkit::terrain::test
