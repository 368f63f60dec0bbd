// Per-frame splat setup and binning into screen tiles. Tiles are the unit of parallel work:
// each tile's fragments are produced from its splat list, which holds splat indices in
// ascending order, so a tile's image does not depend on how tiles are spread over threads.
//
// Deterministic two-pass counting sort over fixed-size chunks of the DrawList: (1) set up every
// splat and count, per chunk, the splats each tile receives; (2) prefix sums in (tile, chunk)
// order; (3) scatter. Memory: one SplatRaster and one TileSpan per splat, one index per
// (splat, tile) overlap, and chunks × tiles counters, all kept from frame to frame; the per-splat
// arrays are left uninitialised (pass 1 writes every entry) and their fresh pages mapped in
// parallel: for a frame of 10 M splats they are 760 MB, whose zeroing and page faults on one
// thread made most of a single frame's time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/setup_splats.h"
#include "splatkit/slot_array.h"

namespace splatkit::render {

inline constexpr int kTileShift = 5;
inline constexpr int kTileSize = 1 << kTileShift;  // pixels per tile side

// The tiles a splat's box touches (tx0 > tx1 when it is not drawn): 8 bytes per splat, so the
// scatter pass does not stream the large SplatRaster array through the cache again.
struct TileSpan {
  uint16_t tx0, tx1, ty0, ty1;
};

struct FrameBins {
  int tiles_x = 0, tiles_y = 0;
  SlotArray<SplatRaster> rasters;    // the first draws.count entries (grows, never shrinks)
  SlotArray<TileSpan> spans;         // the same
  std::vector<uint32_t> offsets;     // #tiles + 1: tile t's splats are indices[offsets[t]...]
  std::vector<uint32_t> indices;     // splat indices, ascending within each tile
  std::vector<uint32_t> counts;      // pass 1's counts per (chunk, tile)
  std::size_t drawn = 0;             // splats with a non-empty box
  double setup_seconds = 0, binning_seconds = 0;  // wall time of pass 1, of passes 2 and 3

  std::size_t tile_count() const { return std::size_t(tiles_x) * tiles_y; }
};

// Fills `bins` (reusing its buffers). Throws Error(kUsage) if draws.count >= 2^32 or the image
// is larger than kMaxImageSide.
void bin_splats(const DrawList& draws, const Projection& projection, const SetupOptions& options,
                FrameBins& bins);

}  // namespace splatkit::render
