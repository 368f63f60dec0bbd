// Rasterisation of one tile: every splat binned to the tile, in ascending splat index order, is
// ray cast over its pixel box clipped to the tile (setup_splats.h); pixels whose ray hits the disc
// add a fragment (depth, Gaussian weight, splat index) to the tile's FragmentStore.
#pragma once

#include <cstdint>

#include "render/fragment_store.h"
#include "render/setup_splats.h"

namespace splatkit::render {

struct TileRect {
  int x0, y0, x1, y1;  // inclusive pixel bounds
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
};

// Weight of a fragment at squared disc radius rho2 in [0, 1]: exp(-kGaussianSharpness · rho2),
// a Gaussian cut off at the disc's rim.
inline constexpr float kGaussianSharpness = 2.0f;
float gaussian_weight(float rho2);

// Returns the number of fragments produced (including any dropped on overflow).
uint64_t rasterize_tile(const SplatRaster* rasters, const uint32_t* splats, std::size_t count,
                        const TileRect& tile, FragmentStore& store);

}  // namespace splatkit::render
