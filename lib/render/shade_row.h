// Deferred shading of a run of pixels on one image row: the colours shade_pixel gives pixel by
// pixel, bit for bit, at a fraction of the cost for Phong. Phong takes three normalisations (nine
// divisions and three square roots) per pixel; here each step runs over the whole run in a loop
// of plain float arithmetic that the compiler vectorises (SSE2 at the x86-64 baseline). It is the
// same C++ on every target, so it needs no SIMD switch: the operations per pixel and their order
// are shade_pixel's (floating-point contraction is off), which tests/unit/test_render_shade_row.cpp
// checks against shade_pixel.
#pragma once

#include "render/camera.h"
#include "render/reconstruct_pixel.h"
#include "render/shade_pixel.h"

namespace splatkit::render {

// Longest run shade_row takes (a tile's width).
inline constexpr int kMaxShadeRun = 32;

// Colours of pixels (x0 + i, y), i < count <= kMaxShadeRun, seen through `projection` (view
// direction towards the eye through each pixel centre), from their G-buffer entries
// `surfaces[i]`. Entries with alpha == 0 (background) get an unspecified colour.
void shade_row(const Shading& shading, const Projection& projection, int x0, int y, int count,
               const PixelSurface* surfaces, Vec3f* colors);

}  // namespace splatkit::render
