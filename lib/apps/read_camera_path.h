// A camera path for splat-view --path: a JSON array of objects
//   {"eye": [x, y, z], "target": [x, y, z], "up": [x, y, z], "fov": degrees}
// with "up" (default `default_up`, or render::automatic_up() of it for a view along it) and
// "fov" (default `default_fov`) optional; one frame per entry, in order. Unknown keys are
// refused (a misspelt "fov" must not pass silently).
#pragma once

#include <string>
#include <vector>

#include "render/camera.h"

namespace splatkit::apps {

// Throws Error(kBadInput) naming `name` and the entry for unreadable JSON, a missing or
// malformed vector, a non-finite number, eye == target, an up parallel to the view, a fov
// outside (0, 180), or an empty array. The cameras get `width` × `height`.
std::vector<render::Camera> read_camera_path(const std::string& text, const std::string& name,
                                             const Vec3f& default_up, float default_fov, int width,
                                             int height);

}  // namespace splatkit::apps
