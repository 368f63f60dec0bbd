// One frame, start to finish: LOD selection -> per-splat setup and tile binning -> per tile (in
// parallel): rasterisation into the tile's A-buffer (fragments in a splat's clip area discarded
// when the scene has clip partners, [IvoMSc] §4.4), surface reconstruction into a tile G-buffer
// (only fragments of one surface id blend, [IvoMSc] §5.5; docs/references.md), deferred shading
// into the Framebuffer.
//
// `--blend zbuffer` (BlendMode::kZBuffer) takes a path of its own instead of the tiles: every splat
// straight into a depth-key buffer (zbuffer_splats.h; QSplat scenes draw from their traversal
// without a DrawList), then each pixel's nearest splat shaded by the same deferred shading.
//
// Deterministic: every tile is computed from its own splat list in splat index order with
// per-tile scratch, so the image is byte-identical for any thread count (threads come from the
// TBB arena the caller runs in). Memory beyond the scene and the framebuffer: one 84-byte
// SplatRaster per splat, a 4-byte index per (splat, tile) overlap, and per thread one tile
// A-buffer (32×32 pixels × (max_fragments + kRingSlots) × 12 bytes).
#pragma once

#include <cstdint>
#include <memory>

#include "render/bin_splats.h"
#include "render/camera.h"
#include "render/framebuffer.h"
#include "render/reconstruct_pixel.h"
#include "render/render_scene.h"
#include "render/select_splats.h"
#include "render/shade_pixel.h"

namespace splatkit::render {

struct RenderOptions {
  BlendMode blend = BlendMode::kZThreshold;
  float epsilon = 0;  // Z-threshold in scene units; <= 0: twice the scene's mean splat radius
  ShadeMode shade = ShadeMode::kPhong;
  int max_fragments = 8;        // A-buffer slots per pixel, 1..kMaxFragmentsPerPixel
  bool cull_backfaces = false;  // off: open surfaces (scans) stay visible from both sides
  bool clip = true;             // discard fragments in the clip areas (scene's clip partners)
  bool surface_ids = true;      // reconstruction blends only fragments of one surface id
  Vec3f background{0.0194f, 0.0232f, 0.0273f};  // linear RGB behind the model (rgb8 only)
  Vec3f default_albedo{0.6f, 0.6f, 0.6f};       // linear, for clouds without colours
  FramebufferPlanes planes;
  float qsplat_threshold_px = 1;  // QSplat scenes: recurse until a node projects this small
  float spt_error_px = 1;         // SPT scenes: the allowed screen error of an entry, pixels
};

struct FrameStats {
  uint64_t splats_in = 0, splats_drawn = 0;
  uint64_t fragments = 0;  // stored in the A-buffer
  uint64_t pixels_covered = 0, pixels_overflowed = 0;
  uint64_t splats_hidden = 0;  // (splat, tile) pairs skipped as hidden behind the tile's surface
  uint64_t fragments_clipped = 0;  // discarded in a clip area (clip_record.h) before the A-buffer
  LodStats lod;                    // QSplat and SPT scenes: the selection's counts
  // Wall-clock seconds per stage. The tile pass runs rasterise, reconstruct and shade per tile;
  // its wall time is split between them in proportion to their summed thread time.
  double select_s = 0, setup_s = 0, binning_s = 0, raster_s = 0, reconstruct_s = 0, shade_s = 0;
  double total_s = 0;
  double splats_per_second() const { return total_s > 0 ? splats_in / total_s : 0; }
};

class FrameRenderer {
 public:
  FrameRenderer();
  ~FrameRenderer();
  // Renders `scene` seen by `camera` into `out` (allocated here). Throws Error(kUsage) for
  // invalid options or cameras.
  FrameStats render(const RenderScene& scene, const Camera& camera, const RenderOptions& options,
                    Framebuffer& out);

 private:
  struct Scratch;
  FrameStats render_zbuffer(const RenderScene& scene, const Projection& projection,
                            const RenderOptions& options, Framebuffer& out);
  FrameBins bins_;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace splatkit::render
