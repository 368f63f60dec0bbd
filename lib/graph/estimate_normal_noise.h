// estimate_normal_noise: how noisy a cloud's normals are, apart from the surface's curvature —
// the switch between segment_surfaces_robust's two core angles.
//
// For a splat S_i with at least 6 continuous neighbours, the normals n_j of the neighbours are
// fitted by an affine function of their tangent coordinates (a, b) = ((C_j − C_i)·u, (C_j −
// C_i)·v) in S_i's frame (u, v, n_i): n_j ≈ c + A (a, b), least squares, one fit per coordinate.
// Curvature is (to first order) exactly such a function, noise is not, so the RMS residual is the
// noise: 0 for exact normals on planes, cylinders and tori alike, the spread of the estimated
// normals for noisy ones (robust normals of the CAD part with 0.125 % noise: several degrees).
#pragma once

#include <cstdint>
#include <span>

#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// graph, edge_flags, sharp_mask as for segment_surfaces; positions, normals: #N each (unit
// normals). Fits about `samples` splats spread evenly over the indices (every ⌈N / samples⌉-th,
// from 0; all when N <= samples) and returns the median of their RMS residuals, in degrees
// (small-angle: the residual vector's length in radians); 0 when no splat qualifies.
// Deterministic; std::invalid_argument on size mismatch or samples 0.
double estimate_normal_noise(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                             uint8_t sharp_mask, std::span<const Vec3f> positions,
                             std::span<const Vec3f> normals, std::size_t samples = 8192);

}  // namespace splatkit::graph
