#include "render/qsplat_scene.h"

#include <algorithm>

#include "formats/describe_qsplat.h"
#include "render/splat_bounds.h"
#include "splatkit/error.h"

namespace splatkit::render {

RenderScene make_qsplat_scene(QSplatModel&& model, const std::string& name) {
  if (model.leaves == 0) throw_bad_input(name, "the QSplat file has no leaves");
  RenderScene s;
  // Framed as the plain render frames the cloud the file was built from: by the sphere
  // build-qsplat recorded from the splats, or in older files by the decoded leaves (not the root
  // sphere, which is loose) with the same rule, which frames the model a little smaller (those
  // files' decoded leaves contain their splats, hence are larger).
  if (const auto view = qsplat_view_sphere(model)) {
    s.bounds.center = {(*view)[0], (*view)[1], (*view)[2]};
    s.bounds.radius = (*view)[3];
    if (const auto box = qsplat_view_box(model)) {  // else framed by the sphere
      s.bounds.box_lo = {(*box)[0], (*box)[1], (*box)[2]};
      s.bounds.box_hi = {(*box)[3], (*box)[4], (*box)[5]};
    }
  } else {
    s.bounds = splat_bounds(model.size(), [&](std::size_t i, Vec3f& c, float& r) {
      c = model.centres[i];
      r = model.radii[i];
      return model.child_count[i] == 0;
    });
  }
  double sum = 0;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (model.child_count[i] == 0) {
      sum += model.radii[i];
      s.max_radius = std::max(s.max_radius, model.radii[i]);
    }
  s.mean_radius = static_cast<float>(sum / static_cast<double>(model.leaves));
  s.origin = qsplat_origin(model);
  s.qsplat = std::make_shared<const QSplatModel>(std::move(model));
  return s;
}

}  // namespace splatkit::render
