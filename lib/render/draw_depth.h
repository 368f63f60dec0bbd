// The depth pass of occlusion culling: splats ray cast (setup_splats.h) into a DepthPyramid's
// level 0, whose cells are kDepthCell × kDepthCell pixels, as upper bounds of the depth of the
// nearest fragment the frame renderer will make at each pixel of the cell. A splat writes a cell
// only when it covers the whole cell: the four corner pixel centres lie inside its projected disc
// (an ellipse, convex, so the pixels between them do too). With cells of 1 pixel it writes its
// far depth (its farthest point, raised by 0.1 %) at every pixel it covers, found per row as the
// run between the first and the last covered pixel (convexity again): one bound per splat, no
// division per pixel, and tighter than the query margin needs; with larger cells, the largest of
// the four corners' depths (the depth of a plane is a monotone function along any line of the
// image, so its maximum over the cell is at a corner). Conservative on purpose, so that a query
// never hides a splat the full render would show: the disc test has a 2 % margin and refuses
// grazing angles, depths are raised by 0.1 % (float round-off of the renderer's own arithmetic is
// far smaller). A splat that would lower nothing (the pyramid over its box is already at most
// what it would write) is skipped. Cells of 1 pixel (kDepthCellShift 0) today: larger cells make
// the pass cheaper, but splats under about 2 cells across then occlude nothing, and distant
// walls of small splats stop hiding what is behind them (measured on the city walkthrough:
// cells of 2 × 2 pixels drew 2.4 × the leaves and 1.9 × the splats).
#pragma once

#include <cstdint>
#include <vector>

#include "render/depth_pyramid.h"
#include "render/render_scene.h"
#include "render/setup_splats.h"

namespace splatkit::render {

inline constexpr int kDepthCellShift = 0;
inline constexpr int kDepthCell = 1 << kDepthCellShift;  // pixels per cell side

// The cells of a pixel rectangle.
inline PixelRect cells_of(const PixelRect& r) {
  return {r.x0 >> kDepthCellShift, r.y0 >> kDepthCellShift, r.x1 >> kDepthCellShift,
          r.y1 >> kDepthCellShift};
}

// A splat's pixel box and nearest depth as the renderer's setup finds them (SplatRaster): the
// per-splat occlusion test's input. Empty box: the renderer draws no fragment of the splat.
struct SplatBounds {
  int16_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive, clipped to the image
  float zmin = 0;
  bool drawn() const { return x0 <= x1; }
};

// Reused buffers of one thread.
struct DepthPassScratch {
  std::vector<Vec3f> positions, normals, axes;
  std::vector<float> radii, minor_radii;
  std::vector<SplatRaster> rasters;
};

// Draws splats `indices[0..count)` of `scene` into `pyramid` level 0 (cells; the pyramid sized
// for the image's cells; safe from several threads at once) and returns the cells written (for
// DepthPyramid::update). Splats are skipped as the renderer skips them: too near, off screen, or
// back-facing with `cull_backfaces`. `bounds[k]` (when not null) receives splat k's SplatBounds;
// with `pyramid` null, only those are computed.
PixelRect draw_depth(const RenderScene& scene, const uint32_t* indices, std::size_t count,
                     const Projection& projection, bool cull_backfaces, DepthPyramid* pyramid,
                     DepthPassScratch& scratch, SplatBounds* bounds = nullptr);

}  // namespace splatkit::render
