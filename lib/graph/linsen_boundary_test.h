// Edge or intersection? Linsen's boundary test on a splat's continuous neighbours ([IvoMSc] §4.1,
// eqs. 4.1, 4.2; Linsen 2001, [Linsen01]; docs/references.md).
#pragma once

#include <span>
#include <vector>

#include "splatkit/vec3.h"

namespace splatkit::graph {

struct BoundaryTestResult {
  bool boundary = true;  // true: S_i lies on a boundary of its smooth surface (an edge);
                         // false: it lies inside a smooth surface that another surface crosses
  double max_gap = 0;    // largest angle between consecutive neighbour directions, radians in
                         // (0, 2π]; 2π when fewer than 2 directions were usable
  int directions = 0;    // neighbours that gave a direction (see below)
};

// c_i, n_i: the splat's centre and unit normal. neighbours: centres C_j of the splats joined to
// S_i by a continuous edge, N_c(S_i) (same frame). alpha: the gap threshold, radians.
//
// Each neighbour gives the direction v'_j = (C_j - C_i) × n_i (eq. 4.2), which lies in S_i's plane
// and is the projection v_j of C_j onto that plane (eq. 4.1) turned by -90° about n_i: the same
// turn for every j, so the gaps between consecutive directions are those between the projections.
// The angle of v'_j is measured in one fixed orthonormal frame (e1, e2, n_i) built from n_i alone
// (Duff et al. 2017, "Building an orthonormal basis, revisited", [Duff17]), atan2(v'_j·e2,
// v'_j·e1); the angles are sorted and the gaps include the wrap-around one, 2π - last + first.
//
// boundary = (fewer than 2 usable directions) or (largest gap > alpha). A neighbour whose centre
// coincides with C_i or lies on the normal line through it (|v'_j| <= 1e-6 |C_j - C_i|) has no
// direction and is skipped; NaN centres are skipped too. With no neighbour at all the splat
// has nothing on any side: an edge. Cost: O(k log k) for k neighbours; `scratch` avoids
// allocating per call (its contents on return are unspecified).
BoundaryTestResult linsen_boundary_test(const Vec3f& c_i, const Vec3f& n_i,
                                        std::span<const Vec3f> neighbours, double alpha,
                                        std::vector<double>& scratch);

// Same, allocating its own scratch.
BoundaryTestResult linsen_boundary_test(const Vec3f& c_i, const Vec3f& n_i,
                                        std::span<const Vec3f> neighbours, double alpha);

}  // namespace splatkit::graph
