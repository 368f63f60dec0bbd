#include "render/qsplat_scene.h"

#include <algorithm>

#include "splatkit/error.h"

namespace splatkit::render {

RenderScene make_qsplat_scene(QSplatModel&& model, const std::string& name) {
  if (model.leaves == 0) throw_bad_input(name, "the QSplat file has no leaves");
  RenderScene s;
  // Bounds of the decoded leaves (not the root sphere, which is loose): frames a .qs model as the
  // plain render frames its splats.
  Vec3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  double sum = 0;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (model.child_count[i] == 0) {
      const Vec3f& c = model.centres[i];
      const float r = model.radii[i];
      lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
      hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
      sum += r;
      s.max_radius = std::max(s.max_radius, r);
    }
  s.bounds.center = (lo + hi) * 0.5f;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (model.child_count[i] == 0)
      s.bounds.radius =
          std::max(s.bounds.radius, norm(model.centres[i] - s.bounds.center) + model.radii[i]);
  s.mean_radius = static_cast<float>(sum / static_cast<double>(model.leaves));
  s.qsplat = std::make_shared<const QSplatModel>(std::move(model));
  return s;
}

}  // namespace splatkit::render
