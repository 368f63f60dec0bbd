// The leaves a QSplat tree is built over: one splat per kept input point.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "splatkit/vec3.h"

namespace splatkit::qsplat {

struct QSplatLeaves {
  std::vector<Vec3f> positions;                // #N splat centres (the cloud's local frame)
  std::vector<Vec3f> normals;                  // #N unit normals
  std::vector<float> radii;                    // #N radii > 0
  std::vector<std::array<uint8_t, 3>> colors;  // #N 8-bit RGB, or empty
  uint64_t dropped_unused = 0;                 // mesh vertices in no face
  uint64_t dropped_zero_radius = 0;  // splats of radius 0, vertices of degenerate faces only
  uint64_t dropped_zero_normal = 0;  // mesh vertices whose faces' normals cancel out
  std::size_t size() const { return positions.size(); }
};

}  // namespace splatkit::qsplat
