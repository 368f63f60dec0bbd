// The splats of a scene a frame draws after occlusion culling, as a scene of their own: the
// arrays of splats `indices` (ascending) of `full`, in that order, with the full scene's bounds
// and radius statistics (which set the renderer's default Z-threshold, depth window and shading),
// so that rendering the subset gives the image of rendering `full` whenever the left-out splats
// have no fragment that reaches reconstruction (occlusion_culler.h). Clip partners are not
// carried (render the subset without clipping, or do not cull scenes with clip partners); a
// QSplat scene is refused with Error(kUsage).
#pragma once

#include <cstdint>
#include <vector>

#include "render/render_scene.h"

namespace splatkit::render {

// Fills `out` (reusing its buffers).
void subset_scene(const RenderScene& full, const std::vector<uint32_t>& indices, RenderScene& out);

}  // namespace splatkit::render
