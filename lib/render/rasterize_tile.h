// Rasterisation of one tile: every splat binned to the tile is ray cast over its pixel box
// clipped to the tile (setup_splats.h); pixels whose ray hits the disc add a fragment (depth,
// Gaussian weight, splat index) to the tile's FragmentStore. Pixels whose ray meets the splat's
// plane in the ring around the disc, out to kRingScale × its radius, add a ring fragment: its
// weight negated, for the normal's reconstruction only (reconstruct_pixel.h).
//
// Order: the splats facing the eye first, then those facing away, each group in ascending splat
// index order. On closed models the front faces then set every pixel's nearest depth before the
// hidden back faces arrive, so the store's depth window drops those at once, and a back-facing
// splat whose whole depth range lies beyond the tile's farthest nearest depth + window is
// skipped without ray casting. What the store keeps (the K nearest disc and kRingSlots nearest
// ring fragments within the window) does not depend on the order, so neither does the image.
//
// Clipping ([IvoMSc] §4.4, docs/references.md): a fragment of a splat with clip partners is
// discarded before it reaches the store when graph::fragment_discarded holds for its 3D point P =
// eye + z·ray (the ray through the pixel centre meeting the splat's plane at camera depth z, in the
// scene frame the clip planes were made in). Splats without partners take the unclipped loop, and a
// frame without clip data passes no ClipContext: no per-fragment cost.
#pragma once

#include <cstdint>

#include "graph/clip_record.h"
#include "render/camera.h"
#include "render/fragment_store.h"
#include "render/setup_splats.h"

namespace splatkit::render {

struct TileRect {
  int x0, y0, x1, y1;  // inclusive pixel bounds
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
};

// Weight of a fragment at squared disc radius rho2 in [0, kRingScale²] (1 at the disc's rim):
// exp(-kGaussianSharpness · rho2) less its value at the ring's rim, a Gaussian that falls to 0
// there ([Botsch05]).
inline constexpr float kGaussianSharpness = 2.0f;
float gaussian_weight(float rho2);

struct RasterCounts {
  uint64_t fragments = 0;       // fragments stored (before any later overflow replacement)
  uint64_t skipped_splats = 0;  // back-facing splats skipped as hidden for the whole tile
  uint64_t clipped = 0;         // fragments discarded by clipping
};

// What the clipped loop needs: the splats' clip rows (indexed like `rasters`) and the frame's
// camera to turn a pixel and a depth into a scene point.
struct ClipContext {
  const graph::ClipPartnerTable* table = nullptr;
  const graph::ClipPlane* planes = nullptr;  // #table->partners
  Projection projection;
};

// `clip`: null, or the frame's clip data (see above).
RasterCounts rasterize_tile(const SplatRaster* rasters, const uint32_t* splats, std::size_t count,
                            const TileRect& tile, FragmentStore& store,
                            const ClipContext* clip = nullptr);

}  // namespace splatkit::render
