#include "render/qsplat_scene.h"

#include <algorithm>

#include "formats/describe_qsplat.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::render {

RenderScene make_qsplat_scene(QSplatModel&& model, const std::string& name) {
  if (model.leaves == 0) throw_bad_input(name, "the QSplat file has no leaves");
  RenderScene s;
  // Bounds of the decoded leaves (not the root sphere, which is loose): frames a .qs model as the
  // plain render frames its splats. In fixed chunks, combined in order: the same sums for any
  // thread count.
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  struct Part {
    Vec3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    double sum = 0;
    float max_radius = 0, reach = 0;
  };
  std::vector<Part> parts(chunk_count(model.size(), kChunk));
  for_each_chunk(model.size(), kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    Part& p = parts[c];
    for (std::size_t i = b; i < e; ++i)
      if (model.child_count[i] == 0) {
        const Vec3f& x = model.centres[i];
        const float r = model.radii[i];
        p.lo = {std::min(p.lo.x, x.x - r), std::min(p.lo.y, x.y - r), std::min(p.lo.z, x.z - r)};
        p.hi = {std::max(p.hi.x, x.x + r), std::max(p.hi.y, x.y + r), std::max(p.hi.z, x.z + r)};
        p.sum += r;
        p.max_radius = std::max(p.max_radius, r);
      }
  });
  Part all;
  for (const Part& p : parts) {
    all.lo = {std::min(all.lo.x, p.lo.x), std::min(all.lo.y, p.lo.y), std::min(all.lo.z, p.lo.z)};
    all.hi = {std::max(all.hi.x, p.hi.x), std::max(all.hi.y, p.hi.y), std::max(all.hi.z, p.hi.z)};
    all.sum += p.sum;
    all.max_radius = std::max(all.max_radius, p.max_radius);
  }
  s.bounds.center = (all.lo + all.hi) * 0.5f;
  for_each_chunk(model.size(), kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    float reach = 0;
    for (std::size_t i = b; i < e; ++i)
      if (model.child_count[i] == 0)
        reach = std::max(reach, norm(model.centres[i] - s.bounds.center) + model.radii[i]);
    parts[c].reach = reach;
  });
  for (const Part& p : parts) s.bounds.radius = std::max(s.bounds.radius, p.reach);
  s.max_radius = all.max_radius;
  s.mean_radius = static_cast<float>(all.sum / static_cast<double>(model.leaves));
  s.origin = qsplat_origin(model);
  s.qsplat = std::make_shared<const QSplatModel>(std::move(model));
  return s;
}

}  // namespace splatkit::render
