// The splats a frame truly shows, counted by rendering ids: every splat drawn into a depth-key
// buffer (zbuffer_splats.h: the nearest splat per pixel, by centre depth, as a screen-aligned
// disc), then the distinct splat indices left in it. The yardstick for what occlusion culling
// draws (occlusion_culler.h): a culler cannot do better than draw the splats some pixel shows.
// Costs a frame of the z-buffer path; a diagnostic (splat-view --count-visible), not a renderer.
#pragma once

#include <cstdint>
#include <vector>

#include "render/camera.h"
#include "render/render_scene.h"

namespace splatkit::render {

// Plain scenes only (positions and radii). `cull_backfaces` as the renderer.
uint64_t count_visible_splats(const RenderScene& scene, const Projection& projection,
                              bool cull_backfaces);
// The same splats' indices, ascending.
std::vector<uint32_t> visible_splats(const RenderScene& scene, const Projection& projection,
                                     bool cull_backfaces);

}  // namespace splatkit::render
