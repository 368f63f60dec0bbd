// orient_normals_viewpoint: `estimate-normals --orient viewpoint`: every normal is made
// to point towards a viewpoint, the scanner position: n_i is flipped when n_i·(v − x_i) < 0. A
// normal perpendicular to the line of sight (dot exactly 0) keeps its sign.
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include "splatkit/vec3.h"

namespace splatkit {

// positions, normals: #N; viewpoint in the positions' frame (the caller subtracts the cloud's
// origin), finite. Returns the number of normals flipped. Runs in parallel; deterministic.
std::size_t orient_normals_viewpoint(std::span<const Vec3f> positions, std::span<Vec3f> normals,
                                     const std::array<double, 3>& viewpoint);

}  // namespace splatkit
