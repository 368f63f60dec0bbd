// A camera path for splat-view --path: a JSON array of objects
//   {"eye": [x, y, z], "target": [x, y, z], "up": [x, y, z], "fov": degrees}
// with "up" (default `default_up`, or render::automatic_up() of it for a view along it) and
// "fov" (default `default_fov`) optional; one frame per entry, in order. Unknown keys are
// refused (a misspelt "fov" must not pass silently). Points are in the file's coordinates: the
// scene's origin (RenderScene::origin) is subtracted, in double precision, to give the cameras
// in the scene's local frame.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "render/camera.h"

namespace splatkit::apps {

// Throws Error(kBadInput) naming `name` and the entry for unreadable JSON, a missing or
// malformed vector, a non-finite number, eye == target, an up parallel to the view, a fov
// outside (0, 180), or an empty array. The cameras get `width` × `height`.
std::vector<render::Camera> read_camera_path(const std::string& text, const std::string& name,
                                             const Vec3f& default_up, float default_fov, int width,
                                             int height,
                                             const std::array<double, 3>& origin = {0, 0, 0});

}  // namespace splatkit::apps
