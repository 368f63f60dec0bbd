// Per-frame splat setup and binning into screen tiles. Tiles are the unit of parallel work:
// each tile's fragments are produced from its splat list, which holds splat indices in
// ascending order, so a tile's image does not depend on how tiles are spread over threads.
//
// Deterministic two-pass counting sort over fixed-size chunks of the DrawList: (1) set up every
// splat and count, per chunk, the splats each tile receives; (2) prefix sums in (tile, chunk)
// order; (3) scatter. Memory: one SplatRaster per splat, one index per (splat, tile) overlap,
// and chunks × tiles counters.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/setup_splats.h"

namespace splatkit::render {

inline constexpr int kTileShift = 5;
inline constexpr int kTileSize = 1 << kTileShift;  // pixels per tile side

struct FrameBins {
  int tiles_x = 0, tiles_y = 0;
  std::vector<SplatRaster> rasters;  // #draws.count
  std::vector<uint32_t> offsets;     // #tiles + 1: tile t's splats are indices[offsets[t]...]
  std::vector<uint32_t> indices;     // splat indices, ascending within each tile
  std::size_t drawn = 0;             // splats with a non-empty box
  double setup_seconds = 0, binning_seconds = 0;  // wall time of pass 1, of passes 2 and 3

  std::size_t tile_count() const { return std::size_t(tiles_x) * tiles_y; }
};

// Fills `bins` (reusing its buffers). Throws Error(kUsage) if draws.count >= 2^32 or the image
// is larger than kMaxImageSide.
void bin_splats(const DrawList& draws, const Projection& projection, const SetupOptions& options,
                FrameBins& bins);

}  // namespace splatkit::render
