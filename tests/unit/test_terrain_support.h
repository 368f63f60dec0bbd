// Shared by the terrain tests: a heightmap source over rows in memory, and a map with its HAM
// tiles and frame.
#pragma once

#include <cstdint>
#include <cstring>
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

}  // namespace splatkit::terrain::test
