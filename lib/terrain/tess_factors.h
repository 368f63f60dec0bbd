// Tessellation factors of terrain tiles for a camera, after the HAM-driven hardware
// tessellation of [Valdetaro10] ([TerrainCh5] eqs. 5-2 to 5-7): per tile, integer factors in
// [1, 64] for its four edges and its interior (0 for a tile outside the view frustum), from
//   T_max = 1 + 63·sqrt(HAM_max / HAM_ref)          (the tile's roughness; HAM_ref: the map's
//                                                     largest HAM, so the roughest tile gets 64)
//   T_min = clamp(log2(ĥ / ε), 1, T_max)             (ĥ: the projected peak height in pixels,
//                                                     ε: the allowed error in pixels)
//   T(d)  = T_max for d < d_max, T_max·d_max²/d² up to d_min = sqrt(T_max/T_min)·d_max, then
//           T_min                                     (d: eye to the reference point)
// and rounded up. To that splatkit adds a bound of the screen-space error itself, so that a small
// ε reaches the map's full resolution where the screen asks for it:
//   κ     = HAM_max / 64                             (the Sobel operator's gain is 8 per pass: a
//                                                     curvature estimate, heights per texel²)
//   T_err = n·sqrt(f·κ·sin θ / (8·d·ε))              (n: the edge's texels, f: focal length in
//                                                     pixels; a segment of L texels departs from
//                                                     a curve of curvature κ by at most κL²/8, a
//                                                     vertical error that projects to
//                                                     f·κL²·sin θ/(8d) pixels, θ: the angle of
//                                                     the line of sight from the vertical)
//   T     = min(max(T(d), T_err), n, 64)             (n segments: one texel per triangle edge,
//                                                     the map's full resolution; no finer)
// So ε → 0 gives every tile with any curvature n segments (tiles of more than 64 texels stop at
// 64, as a GPU's tessellator does), except where the line of sight is exactly vertical; a flat
// tile (HAM 0) keeps T(d). An edge shared by two tiles
// takes the larger T_max, κ and peak of the two, and its midpoint as reference point, so that
// both tiles compute the same factor from the same inputs and the tessellated mesh has no cracks.
// The interior uses the tile's own T_max and κ, its longer side as n, and its centre raised to
// its peak height h_max.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "render/camera.h"
#include "terrain/ham_tiles.h"

namespace splatkit::terrain {

// Where the map lies in the scene: texel (x, y) at (x·sx, -y·sy) (row 0 north, +y up on a map),
// heights as stored in the tiles (already scaled by z_scale).
struct TerrainFrame {
  double sx = 1, sy = 1;
  double h_min = 0;                            // the map's lowest (filled) height
  double ham_ref = 0;                          // the map's largest HAM (0: flat)
};

struct TessSettings {
  float error_px = 2;       // ε, pixels (> 0)
  float d_max_tiles = 3;    // d_max in tile diagonals
};

// Factors of one tile: edges 0 north (y = ty·T), 1 east (x = (tx+1)·T), 2 south, 3 west.
struct TileFactors {
  std::array<int, 4> edge{0, 0, 0, 0};
  int inner = 0;
  bool visible() const { return inner > 0; }
};

// The factor of a reference point: T_max, the peak height over the map's base, the point, the
// camera; `curvature` κ (heights per texel², 0: the paper's factor alone) and `texels` n (the
// segments of full resolution, ≥ 1). Exposed for the tests.
int tess_factor(float t_max, double peak, const Vec3f& point, const render::Projection& camera,
                double d_max, const TessSettings& settings, double curvature = 0,
                int64_t texels = 64);

// κ of a tile from its HAM_max.
double tile_curvature(float ham_max);

float tile_t_max(float ham_max, double ham_ref);

// The texel extent of tile (tx, ty): [x0, x1] × [y0, y1], neighbours sharing their border texels.
struct TileExtent {
  int64_t x0, x1, y0, y1;
};
TileExtent tile_extent(const HamTiles& tiles, int64_t tx, int64_t ty);

// `height(x, y)`: the filled, scaled height at texel coordinates (bilinear), for reference
// points' heights. Every tile computes its own four edges (each from itself and its neighbour).
using HeightAt = double (*)(const void* context, double x, double y);
std::vector<TileFactors> tess_factors(const HamTiles& tiles, const TerrainFrame& frame,
                                      const render::Projection& camera,
                                      const TessSettings& settings, HeightAt height,
                                      const void* context);

}  // namespace splatkit::terrain
