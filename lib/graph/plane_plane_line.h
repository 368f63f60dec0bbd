// The line where the planes of two splats meet ([IvoMSc] §4.2.1, eqs. 4.3–4.7;
// docs/references.md).
#pragma once

#include <optional>

#include "graph/geometry_types.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// Planes: {P : n_i·P = n_i·C_i} and {P : n_j·P = n_j·C_j}, C and n in the same frame, normals of
// any non-zero length (unit in practice). Returns the line P_o + t d with
//   d   = (n_i × n_j) / |n_i × n_j|   — eq. 4.4, normalised so that t is a length;
//   P_o = R + t_i n_i + t_j n_j       — eqs. 4.5–4.7, with (t_i, t_j) solving the 2×2 system (4.6)
//         n_i·P_o = n_i·C_i, n_j·P_o = n_j·C_j. The thesis takes R = the origin; here R is the
//         midpoint of C_i and C_j, so P_o is the point of the line nearest that midpoint and far
//         coordinates do not cost precision. P_o does not depend on which splat is i.
// Computed in double. Returns no line (std::nullopt) when the planes are parallel or coincident
// — sin²(angle between the normals) <= min_sin2 — when a normal is zero, or when any input is
// NaN. For a sharp edge (n_i·n_j < w_s = 0.9) sin² > 0.19, far from the default threshold.
std::optional<Line3> plane_plane_line(const Vec3f& c_i, const Vec3f& n_i, const Vec3f& c_j,
                                      const Vec3f& n_j, double min_sin2 = 1e-12);

}  // namespace splatkit::graph
