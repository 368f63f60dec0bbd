// A disc of a Sequential Point Tree [Dachsbacher03] and the errors of a parent disc fitted to its
// children.
#pragma once

#include <span>

#include "splatkit/vec3.h"

namespace splatkit::spt {

struct SptDisc {
  Vec3f centre{0, 0, 0};
  Vec3f normal{0, 0, 1};      // unit
  float radius = 0;           // scene units
  Vec3f color{0, 0, 0};       // 8-bit RGB as floats in [0, 255], or zero without colour
  float color_deviation = 0;  // bound on |color − any leaf colour below|, max channel, in [0, 1]
  float error = 0;            // geometric error e_g, made monotone (>= every child's); leaves 0
};

// The errors of `parent` over `children` [Dachsbacher03] §3 (scene units):
//   e_p = max_i((c_i − c)·n + d_i) − min_i((c_i − c)·n − d_i), d_i = r_i·√(1 − (n_i·n)²)
//   e_t = max_k max(0, r − h_k), h_k = max_i(u_k·(c_i − c) + r_i·√(1 − (u_k·n_i)²)) over the 8
//         in-plane directions u_k at k·45° from an axis of the parent's plane
// (e_p: the thickness of the slab about the parent's plane that holds the children; e_t: how far
// the parent disc reaches beyond the children in the plane).
struct DiscErrors {
  float perpendicular = 0, tangential = 0;
};
DiscErrors disc_errors(const SptDisc& parent, std::span<const SptDisc> children);

// The parent disc of `children` (at least one): centre = mean of the child centres weighted by
// their areas r_i² (plain mean when every radius is 0), normal = the area-weighted sum of the
// child normals normalised (the largest child's normal when the sum vanishes), radius = max_i(|t_i|
// + r_i) with t_i the in-plane part of c_i − c (the disc covers every child's projection), colour
// = the area-weighted mean, colour_deviation = max_i(‖col_i − col‖∞/255 + dev_i), and error =
// max(√(e_p² + e_t² + e_c²), max_i error_i) with e_c = color_weight · 2r · colour_deviation (so
// textured flat areas keep refining). `has_color`: whether colours take part.
SptDisc fit_spt_disc(std::span<const SptDisc> children, float color_weight, bool has_color);

}  // namespace splatkit::spt
