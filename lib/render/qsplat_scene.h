// A render scene over a QSplat hierarchy (.qs): frames draw what select_qsplat.h selects.
#pragma once

#include "formats/read_qsplat.h"
#include "render/render_scene.h"

namespace splatkit::render {

// Bounds, mean_radius and max_radius: those of the decoded leaves (the bounds frame the model as
// the plain render frames its splats; the radii set the default blending epsilon). Throws Error(kBadInput) naming
// `name` when the model has no leaves.
RenderScene make_qsplat_scene(QSplatModel&& model, const std::string& name);

}  // namespace splatkit::render
