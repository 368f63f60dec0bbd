#include "render/qsplat_scene.h"

#include <algorithm>

#include "splatkit/error.h"

namespace splatkit::render {

RenderScene make_qsplat_scene(QSplatModel&& model, const std::string& name) {
  if (model.leaves == 0) throw_bad_input(name, "the QSplat file has no leaves");
  RenderScene s;
  const uint32_t r0 = model.roots[0];
  s.bounds = {model.centres[r0], model.radii[r0]};
  for (uint32_t r : model.roots)
    s.bounds.radius =
        std::max(s.bounds.radius, norm(model.centres[r] - s.bounds.center) + model.radii[r]);
  double sum = 0;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (model.child_count[i] == 0) {
      sum += model.radii[i];
      s.max_radius = std::max(s.max_radius, model.radii[i]);
    }
  s.mean_radius = static_cast<float>(sum / static_cast<double>(model.leaves));
  s.qsplat = std::make_shared<const QSplatModel>(std::move(model));
  return s;
}

}  // namespace splatkit::render
