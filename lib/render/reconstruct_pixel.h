// Surface reconstruction of one pixel from its A-buffer fragments ([IvoMSc] ch. 5;
// docs/references.md).
//
// Fragments are disc fragments (positive weight) or ring fragments (negative weight: the ring
// around a splat large on screen, rasterize_tile.h), sorted front to back by depth (ties by splat
// index). The adapted method of [IvoMSc] §5.5 finds the nearest disc fragment f1, sets aside the
// fragments of other surface ids, and runs the classic method on the rest from f1, forward and
// backward (ring fragments just in front of f1 join too):
//   Z-threshold (Zwicker et al. 2001, [Zwicker01]): the next fragment joins while its depth is
//     less than epsilon beyond the previous joined one;
//   Z-range (Räsänen 2002, [Rasanen02]): the next fragment joins while its splat's depth range
//     overlaps the union of the joined fragments' ranges.
// When some joined disc fragments face the eye (their splat's normal towards it), the fragments
// facing away are set aside: a back face within the threshold of a front face (the far side of a
// thin part, the hidden wall of a crevice) must not turn the front's normal. The rest are blended
// by their weights, c = Σ c_k w_k / Σ w_k (eq. 5.2; colour and depth over the disc fragments),
// normalised per pixel as [Botsch05] does. The normal is that mean over disc and ring fragments
// made linearly precise: a weighted least-squares fit of a linear normal field over the splats'
// centres, evaluated at the pixel's surface point ([Lancaster81]; reconstruct_pixel.cpp), which
// removes the mean's bias towards the side of the pixel with more splats and leaves shading
// without the splats' facets; pixels whose f1 has no ring (a splat under kRingMinPx) take the
// plain mean. Ring fragments in front of f1 that do not chain to it cover the pixel themselves
// when it is a pinhole in their surface: their splats' centres surround it, or they face the eye
// and f1 faces away. Ring fragments alone cover nothing else. Surfaces composite front to back
// (eq. 5.1); splats are opaque, so the first surface decides the pixel. Without surface ids every
// fragment is on surface 0 and the method is the classic one.
#pragma once

#include <cstdint>
#include <limits>

#include "render/fragment_store.h"
#include "render/select_splats.h"
#include "render/setup_splats.h"

namespace splatkit::render {

// kZBuffer: no reconstruction at all, the nearest splat per pixel (zbuffer_splats.h); the frame
// renderer takes its own path for it and never calls the functions below with it.
enum class BlendMode { kZThreshold, kZRange, kZBuffer };

struct BlendOptions {
  BlendMode mode = BlendMode::kZThreshold;
  float epsilon = 0;  // Z-threshold, scene units (> 0)
  // Fragments deeper than this behind the nearest disc fragment are ignored (FragmentStore's
  // window).
  float window = std::numeric_limits<float>::infinity();
};

// The smallest depth window that cannot cut the front surface of a pixel holding at most
// `capacity` disc fragments: a Z-threshold chain spans less than (capacity − 1)·ε; a Z-range
// chain ends before the nearest fragment's depth + capacity × the widest splat depth range with
// its ring (2 × kRingScale × max_radius).
float depth_window(BlendMode mode, float epsilon, float max_radius, int capacity);

struct PixelSurface {
  Vec3f normal{0, 0, 0};  // fitted, not normalised (zero when nothing covers the pixel)
  Vec3f albedo{0, 0, 0};  // blended linear colour
  float depth = 0;        // blended camera depth
  float alpha = 0;        // coverage: 1 when a surface covers the pixel
  uint32_t surface_id = 0;
};

// Maximum fragments per pixel the reconstruction accepts (FragmentStore capacity).
inline constexpr int kMaxFragmentsPerPixel = 64;

// The pixel's ray in camera space, (x, y, 1) (right, down, forward): its point at camera depth z
// is z·(x, y, 1) relative to the eye.
struct PixelRay {
  float x = 0, y = 0;
};

// The ray through the centre of image pixel (x, y).
PixelRay pixel_ray(const Projection& projection, int x, int y);

// `depths`, `weights`, `splats`: #count fragments in any order (count <= kMaxFragmentsPerPixel +
// kRingSlots), disc fragments with positive weights, ring fragments with negative ones
// (rasterize_tile.h).
// `default_albedo` is used when the DrawList has no colours. Reads the splats' normals, facing
// (nc), camera-space centres and radii from `rasters`, their colours and surface ids from `draws`.
PixelSurface reconstruct_pixel(const float* depths, const float* weights, const uint32_t* splats,
                               int count, const DrawList& draws, const SplatRaster* rasters,
                               const BlendOptions& options, const Vec3f& default_albedo,
                               const PixelRay& ray);

// Where a tile's pixels lie in the image: pixel p of the tile is image pixel
// (x0 + p % width, y0 + p / width).
struct TilePixels {
  const Projection* projection = nullptr;
  int x0 = 0, y0 = 0, width = 1;
};

// A tile's G-buffer: out[p] = reconstruct_pixel of pixel p's fragments in `store`, p < pixels,
// or alpha 0 (nothing else set) where a pixel has none. Returns the number of covered pixels and
// adds the overflowed ones to `overflowed`. The same results as calling reconstruct_pixel per
// pixel, without a call per pixel.
int reconstruct_pixels(const FragmentStore& store, int pixels, const DrawList& draws,
                       const SplatRaster* rasters, const BlendOptions& options,
                       const Vec3f& default_albedo, const TilePixels& tile, PixelSurface* out,
                       uint64_t& overflowed);

}  // namespace splatkit::render
