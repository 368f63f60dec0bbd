#include "render/count_visible_splats.h"

#include <oneapi/tbb/parallel_for.h>

#include <vector>

#include "render/zbuffer_splats.h"

namespace splatkit::render {

namespace {

// One bit per splat: set when some pixel shows it.
std::vector<uint64_t> visible_mask(const RenderScene& scene, const Projection& projection,
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
  for (uint64_t key : zb.keys) {
    if (key == kNoSplatKey) continue;
    const uint32_t i = DepthKeyBuffer::index_of(key);
    seen[i >> 6] |= uint64_t{1} << (i & 63);
  }
  return seen;
}

}  // namespace

uint64_t count_visible_splats(const RenderScene& scene, const Projection& projection,
                              bool cull_backfaces) {
  uint64_t count = 0;
  for (uint64_t w : visible_mask(scene, projection, cull_backfaces))
    count += __builtin_popcountll(w);
  return count;
}

std::vector<uint32_t> visible_splats(const RenderScene& scene, const Projection& projection,
                                     bool cull_backfaces) {
  std::vector<uint32_t> ids;
  const std::vector<uint64_t> seen = visible_mask(scene, projection, cull_backfaces);
  for (std::size_t w = 0; w < seen.size(); ++w)
    for (uint64_t bits = seen[w]; bits != 0; bits &= bits - 1)
      ids.push_back(uint32_t(w * 64 + __builtin_ctzll(bits)));
  return ids;
}

}  // namespace splatkit::render
