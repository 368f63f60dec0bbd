// The images one frame produces, each plane only when asked for (an 8-bit PNG needs only rgb8).
// Row-major, top row first, width × height pixels.
#pragma once

#include <cstdint>
#include <vector>

#include "graph/segment_surfaces.h"

namespace splatkit::render {

struct FramebufferPlanes {
  bool rgb8 = true;          // 8-bit colour over the background, sRGB-encoded when the shading is
                             // linear (phong, flat)
  bool float_color = false;  // linear RGBA, premultiplied by coverage (background 0)
  bool aovs = false;         // depth, normal, alpha
  bool surface_ids = false;  // surface id of the front surface (kNoSurfaceId on background)
};

// The surface id of background pixels (and of splats that belong to no surface).
inline constexpr uint32_t kNoSurfaceId = graph::kNoSurface;

struct Framebuffer {
  int width = 0, height = 0;
  FramebufferPlanes planes;
  std::vector<uint8_t> rgb8;  // #H×W×3
  std::vector<float> rgba;    // #H×W×4
  std::vector<float> depth;   // #H×W camera depth (scene units), +inf where nothing is drawn
  std::vector<float> normal;  // #H×W×3 unit world-space normal, 0 where nothing is drawn
  std::vector<float> alpha;   // #H×W coverage in [0, 1]
  std::vector<uint32_t> surface_id;  // #H×W front surface's id (0 when the scene has none)

  // Sizes the requested planes (contents are overwritten by every frame).
  void allocate(int w, int h, const FramebufferPlanes& p) {
    width = w;
    height = h;
    planes = p;
    const std::size_t n = std::size_t(w) * h;
    rgb8.resize(p.rgb8 ? n * 3 : 0);
    rgba.resize(p.float_color ? n * 4 : 0);
    depth.resize(p.aovs ? n : 0);
    normal.resize(p.aovs ? n * 3 : 0);
    alpha.resize(p.aovs ? n : 0);
    surface_id.resize(p.surface_ids ? n : 0);
  }
};

}  // namespace splatkit::render
