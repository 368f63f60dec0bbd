// One frame with occlusion culling (occlusion_culler.h): the splats the culler cannot prove
// hidden, rendered by the FrameRenderer; the image is byte for byte that of rendering every
// splat. chc++ after its first frame draws in two sets, with no depth pass of its own: the
// splats the previous frame drew from its visible leaves are rasterised first, the nearest
// disc-fragment depth of each pixel of those A-buffers becomes the culler's pyramid, the culler
// queries the rest against it, and what it cannot prove hidden is added to the same A-buffers
// before reconstruction (FrameRenderer::render_first, render_rest). Every other mode and
// chc++'s first frame: the culler's own depth pass chooses the splats (OcclusionCuller::cull),
// then they are rendered as a scene of their own (subset_scene.h).
#pragma once

#include "render/frame_renderer.h"
#include "render/occlusion_culler.h"

namespace splatkit::render {

// Renders `scene` seen by `camera` into `out`, culling with `culler` (built for `scene`) in
// `mode`; `margin`: the renderer's depth window for `options` (depth_window). `subset`: reused
// scratch. The culling counts and times go to `occlusion`; the returned stats count its time in
// select_s and total_s, and splats_in is the splats drawn.
FrameStats render_culled_frame(const RenderScene& scene, const Camera& camera,
                               const RenderOptions& options, OcclusionMode mode, float margin,
                               OcclusionCuller& culler, FrameRenderer& renderer,
                               RenderScene& subset, Framebuffer& out, OcclusionStats& occlusion);

}  // namespace splatkit::render
