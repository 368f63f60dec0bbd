// orient_normals_viewpoint: `estimate-normals --orient viewpoint`: every normal is made
// to point towards a viewpoint, the scanner position: n_i is flipped when n_i·(v − x_i) < 0. A
// normal perpendicular to the line of sight (dot exactly 0) keeps its sign. Also its variants:
// towards each point's own sensor position (`--orient sensor`: scans merged from several
// stations, mobile mapping), and towards a direction (`--orient up`: aerial scans, as PDAL's
// normal filter orients them by default).
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

// The same with one viewpoint per point (#N, the positions' frame).
std::size_t orient_normals_sensors(std::span<const Vec3f> positions, std::span<Vec3f> normals,
                                   std::span<const std::array<double, 3>> sensors);

// Every normal made to have n·up >= 0 (a normal perpendicular to `up` keeps its sign).
std::size_t orient_normals_up(std::span<Vec3f> normals, const Vec3f& up);

}  // namespace splatkit
