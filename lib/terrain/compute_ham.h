// The height acceleration map (HAM) of a heightmap, streamed: M = |Sobel(H)| (the Sobel
// gradient magnitude [Sobel68], sqrt(Dx² + Dy²) with the 3×3 operators), HAM = |Sobel(M)|, both
// with clamp-to-edge borders, reduced to per-tile records (ham_tiles.h). The map is read in bands
// of rows; each thread takes a run of rows of a band and fuses the two passes over a ring of three
// M rows, so memory holds one band and a few rows, whatever the map's height. No-data samples are
// filled first (fill_voids.h), and the HAM of the texels that depend on a filled sample is bounded
// by the HAM of the valid terrain around them (kVoidRing; formats/ham.md, "Voids").
#pragma once

#include <cstdint>
#include <functional>

#include "splatkit/progress.h"
#include "terrain/ham_tiles.h"
#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

// The HAM of a texel within 2 texels (Chebyshev) of a replaced sample (a void or a void edge,
// fill_voids.h) depends on filled heights: it is clamped to the largest HAM of the texels within
// kVoidRing texels of it (Chebyshev) that are not within 2 texels of a replaced sample; to 0 when
// there is none. Filled voids never raise the HAM above the terrain around them.
inline constexpr int64_t kVoidRing = 32;

struct HamOptions {
  int64_t tile = 64;
  double z_scale = 1;
  bool has_nodata = false;  // overrides the source's own no-data value when set
  double nodata = 0;
  // Bytes of rows a band may hold (the band is at least 8 rows and a reader band).
  int64_t band_bytes = int64_t(8) << 20;
};

struct HamStats {
  uint64_t samples = 0, voids = 0, void_rows = 0;  // void_rows: rows with no valid sample
  double h_min = 0, h_max = 0;                      // filled, scaled heights
  double ham_max = 0;
  int64_t band_rows = 0;
};

// Called with each band of full-resolution HAM rows, in order (rows × width floats).
using HamRowSink = std::function<void(int64_t rows, const float* data)>;

// Throws what the source throws, Error(kUsage) for a tile size < 1 or > 65536.
HamTiles compute_ham(HeightmapSource& source, const HamOptions& options, HamStats& stats,
                     const HamRowSink& sink = nullptr, const ProgressFn& progress = no_progress());

}  // namespace splatkit::terrain
