// A render scene over a Sequential Point Tree's list (.spt): frames draw what select_spt.h selects.
#pragma once

#include "formats/read_spt.h"
#include "render/render_scene.h"

namespace splatkit::render {

// Bounds: a sphere around the leaves' discs that also holds every entry's centre (the nearest
// distance of select_spt.h must hold for all of them); mean_radius and max_radius: those of the
// leaves (the default blending epsilon, as for the plain render of the same cloud). Throws
// Error(kBadInput) naming `name` when the list has no leaves.
RenderScene make_spt_scene(SptModel&& model, const std::string& name);

}  // namespace splatkit::render
