#include "render/subset_scene.h"

#include <oneapi/tbb/parallel_for.h>

#include "splatkit/error.h"

namespace splatkit::render {

namespace {

template <class T>
void gather(const std::vector<T>& from, const std::vector<uint32_t>& indices, std::vector<T>& to) {
  if (from.empty()) {
    to.clear();
    return;
  }
  to.resize(indices.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, indices.size(), 1 << 15),
                    [&](const auto& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) to[k] = from[indices[k]];
                    });
}

}  // namespace

void subset_scene(const RenderScene& full, const std::vector<uint32_t>& indices, RenderScene& out) {
  if (full.qsplat) throw_usage("occlusion culling needs a plain splat scene, not a QSplat file");
  gather(full.positions, indices, out.positions);
  gather(full.normals, indices, out.normals);
  gather(full.radii, indices, out.radii);
  gather(full.axes, indices, out.axes);
  gather(full.minor_radii, indices, out.minor_radii);
  gather(full.colors, indices, out.colors);
  gather(full.surface_ids, indices, out.surface_ids);
  out.bounds = full.bounds;
  out.mean_radius = full.mean_radius;
  out.max_radius = full.max_radius;
}

}  // namespace splatkit::render
