#include "render/render_culled_frame.h"

#include "render/subset_scene.h"
#include "splatkit/seconds_since.h"

namespace splatkit::render {

FrameStats render_culled_frame(const RenderScene& scene, const Camera& camera,
                               const RenderOptions& options, OcclusionMode mode, float margin,
                               OcclusionCuller& culler, FrameRenderer& renderer,
                               RenderScene& subset, Framebuffer& out, OcclusionStats& occlusion) {
  const auto c0 = Clock::now();
  const Projection projection = make_projection(camera);
  if (const std::vector<uint32_t>* first =
          culler.begin_two_sets(projection, mode, margin, options.cull_backfaces, occlusion)) {
    double cull_s = seconds_since(c0);
    renderer.render_first(scene, *first, camera, options, culler.front());
    const auto c1 = Clock::now();
    const std::vector<uint32_t>& rest = culler.cull_rest(occlusion);
    cull_s += seconds_since(c1);
    FrameStats f = renderer.render_rest(scene, rest, out);
    f.select_s += cull_s;
    f.total_s = seconds_since(c0);
    return f;
  }
  const std::vector<uint32_t>& draw =
      culler.cull(projection, mode, margin, options.cull_backfaces, occlusion);
  subset_scene(scene, draw, subset);
  const double cull_s = seconds_since(c0);
  FrameStats f = renderer.render(subset, camera, options, out);
  f.select_s += cull_s;  // culling is the selection of what to draw
  f.total_s += cull_s;
  return f;
}

}  // namespace splatkit::render
