// Per-splat setup for rasterisation by local ray casting (Botsch et al. 2004, [Botsch04] in
// docs/references.md), exact under perspective: for each splat, the pixel box its projected disc
// covers and three linear functions of the pixel that give, per pixel, the ray's hit point in disc
// coordinates and its depth with one division.
//
// For the ray d(i, j) through the centre of pixel (i, j) (forward component 1) and a disc with
// centre c (relative to the eye), unit normal n, radius r and in-plane unit axes a, b:
//   L = n·d,  U = (n·c)(a·d)/r − (a·c)(n·d)/r,  V = likewise with b,
// all linear in (i, j). The ray meets the plane at depth z = (n·c)/L, at disc coordinates
// (U/L, V/L); the pixel is inside the disc iff U² + V² ≤ L².
// The box is the exact bounding box of the projected disc (an ellipse under perspective): the
// tangent lines x = const and y = const of the dual conic K[r²(I − nnᵀ) − ccᵀ]Kᵀ, solved
// relative to the projected centre (setup_splats.cpp) so that float keeps it accurate.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/camera.h"
#include "render/select_splats.h"

namespace splatkit::render {

// Splats more than kRingMinPx in radius on screen are drawn with a ring around them out to
// kRingScale × their radii: the ring's pixels add fragments that only the normal's reconstruction
// uses (rasterize_tile.h), so that normals blend over wider kernels where splats barely overlap
// ([Botsch05]) and a cover's pinholes close (reconstruct_pixel.h). Smaller splats, whose facets
// would be a pixel or two, go without: the ring would cost half as many fragments again.
inline constexpr float kRingScale = 1.25f;
inline constexpr float kRingMinPx = 3.0f;

struct alignas(16) SplatRaster {
  // What reconstruction reads, first, so that it mostly lies in one cache line (the rest is for
  // rasterising). nc = n·c: the fragment's depth is nc / L, and nc <= 0 when the splat faces the
  // eye. The splat's unit normal (scene frame), read from here, still in cache from rasterising
  // the tile, rather than from the DrawList. Its centre's camera-space x (right) and y (down)
  // relative to the eye, scene units: for reconstruction's normal fit.
  float nc;
  Vec3f normal;
  float cx, cy;
  // Coefficients of L, U, V as f[0]·(i − x0) + f[1]·(j − y0) + f[2]: value at the box corner.
  float l[3], u[3], v[3];
  float zmin, zmax;  // camera-depth range of the disc with its ring (Z-range reconstruction)
  float ring2;       // squared outer radius of the ring, in radii: kRingScale² or 1 (no ring)
  int16_t x0, y0, x1, y1;  // inclusive pixel box clipped to the image; x0 > x1 when not drawn

  bool drawn() const { return x0 <= x1; }
};

struct SetupOptions {
  bool cull_backfaces = false;  // drop splats whose normal faces away from the eye
};

// Largest image side the 16-bit boxes allow.
inline constexpr int kMaxImageSide = 16384;

// Fills out[k] for splats begin..end-1 of `draws` (out has end - begin entries). A splat is not
// drawn when any part of its disc is nearer than projection.near (or behind the eye), when its
// box misses the image, or when back-face culling drops it. Returns the number drawn.
std::size_t setup_splats(const DrawList& draws, const Projection& projection,
                         const SetupOptions& options, std::size_t begin, std::size_t end,
                         SplatRaster* out);

}  // namespace splatkit::render
