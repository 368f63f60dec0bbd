#include "render/count_visible_splats.h"

#include <oneapi/tbb/parallel_for.h>

#include <vector>

#include "render/zbuffer_splats.h"

namespace splatkit::render {

uint64_t count_visible_splats(const RenderScene& scene, const Projection& projection,
                              bool cull_backfaces) {
  DepthKeyBuffer zb;
  zb.reset(projection.width, projection.height);
  const std::size_t n = scene.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (cull_backfaces && dot(scene.normals[i], scene.positions[i] - projection.eye) > 0)
        continue;
      zbuffer_splat(zb, projection, projection.to_camera(scene.positions[i]), scene.radii[i],
                    static_cast<uint32_t>(i));
    }
  });
  std::vector<uint64_t> seen((n + 63) / 64, 0);
  uint64_t count = 0;
  for (uint64_t key : zb.keys) {
    if (key == kNoSplatKey) continue;
    const uint32_t i = DepthKeyBuffer::index_of(key);
    const uint64_t bit = uint64_t{1} << (i & 63);
    count += (seen[i >> 6] & bit) == 0;
    seen[i >> 6] |= bit;
  }
  return count;
}

}  // namespace splatkit::render
