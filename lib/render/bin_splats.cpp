#include "render/bin_splats.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "splatkit/error.h"
#include "splatkit/seconds_since.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::render {

namespace {

constexpr std::size_t kChunk = 16384;

inline TileSpan tile_span(const SplatRaster& s) {
  if (!s.drawn()) return {1, 0, 0, 0};
  return {uint16_t(s.x0 >> kTileShift), uint16_t(s.x1 >> kTileShift), uint16_t(s.y0 >> kTileShift),
          uint16_t(s.y1 >> kTileShift)};
}

template <typename Fn>
inline void for_each_tile(const TileSpan& s, int tiles_x, Fn&& fn) {
  for (int ty = s.ty0; ty <= s.ty1; ++ty)
    for (int tx = s.tx0; tx <= s.tx1; ++tx) fn(std::size_t(ty) * tiles_x + tx);
}

}  // namespace

void bin_splats(const DrawList& draws, const Projection& projection, const SetupOptions& options,
                FrameBins& bins) {
  if (draws.count >= (std::size_t{1} << 32)) throw_usage("too many splats for one frame (2^32)");
  if (projection.width > kMaxImageSide || projection.height > kMaxImageSide)
    throw_usage("image sides are limited to " + std::to_string(kMaxImageSide) + " pixels");
  auto t0 = std::chrono::steady_clock::now();
  bins.tiles_x = (projection.width + kTileSize - 1) >> kTileShift;
  bins.tiles_y = (projection.height + kTileSize - 1) >> kTileShift;
  const std::size_t tiles = bins.tile_count();
  const std::size_t n = draws.count;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  if (bins.rasters.size < n) {
    bins.rasters.allocate(n);
    map_pages_in_parallel(bins.rasters.get(), bins.rasters.get() + n);
    bins.spans.allocate(n);
    map_pages_in_parallel(bins.spans.get(), bins.spans.get() + n);
  }
  std::vector<uint32_t>& counts = bins.counts;
  counts.resize(chunks * tiles);  // every row is cleared below
  std::vector<std::size_t> drawn(chunks);
  TileSpan* const spans = bins.spans.get();

  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    const std::size_t begin = c * kChunk, end = std::min(n, begin + kChunk);
    SplatRaster* out = bins.rasters.get() + begin;
    drawn[c] = setup_splats(draws, projection, options, begin, end, out);
    uint32_t* row = counts.data() + c * tiles;
    std::fill(row, row + tiles, 0u);
    for (std::size_t i = begin; i < end; ++i) {
      spans[i] = tile_span(out[i - begin]);
      for_each_tile(spans[i], bins.tiles_x, [&](std::size_t t) { ++row[t]; });
    }
  });
  bins.setup_seconds = seconds_since(t0);
  auto t1 = std::chrono::steady_clock::now();

  bins.drawn = 0;
  for (std::size_t d : drawn) bins.drawn += d;
  bins.offsets.assign(tiles + 1, 0);
  std::size_t running = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    bins.offsets[t] = static_cast<uint32_t>(running);
    for (std::size_t c = 0; c < chunks; ++c) {
      uint32_t k = counts[c * tiles + t];
      counts[c * tiles + t] = static_cast<uint32_t>(running);
      running += k;
    }
  }
  if (running >= (std::size_t{1} << 32)) throw_usage("too many splat-tile overlaps in one frame");
  bins.offsets[tiles] = static_cast<uint32_t>(running);
  bins.indices.resize(running);

  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    const std::size_t begin = c * kChunk, end = std::min(n, begin + kChunk);
    uint32_t* cursor = counts.data() + c * tiles;
    for (std::size_t i = begin; i < end; ++i)
      for_each_tile(spans[i], bins.tiles_x,
                    [&](std::size_t t) { bins.indices[cursor[t]++] = static_cast<uint32_t>(i); });
  });
  bins.binning_seconds = seconds_since(t1);
}

}  // namespace splatkit::render
