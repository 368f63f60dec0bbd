// Concave or convex? The classification of a splat's clip partners ([IvoMSc] §4.3, eqs. 4.13–4.15;
// docs/references.md).
//
// "S sees P" means (P - C_S)·n_S > 0. Every test compares a signed distance with a tolerance
// `tol` (a length, >= 0): a value in [-tol, tol] counts as zero, so coplanar configurations
// (a straight crease between two flat faces, where the exact values are 0) classify as kFlat
// instead of by the sign of rounding noise.
#pragma once

#include <cstdint>
#include <span>

#include "splatkit/vec3.h"

namespace splatkit::graph {

enum class Convexity : uint8_t {
  kConcave,  // every value >= -tol and at least one > tol
  kConvex,   // every value <= tol and at least one < -tol
  kFlat,     // every value in [-tol, tol] (also: an empty set, a single partner in eq. 4.13)
  kMixed,    // some > tol and some < -tol: the thesis's method has no answer (its §4.5, §7.3)
};

// Which side of a partner's plane is its clip area (eq. 4.17).
enum class ClipSide : uint8_t {
  kBehind,  // S ∪ N_cp concave (S sees its partners): area = {P : (P - C_j)·n_j < 0}
  kFront,   // S ∪ N_cp convex: area = {P : (P - C_j)·n_j > 0}
};

// How the partners' clip areas combine (eqs. 4.15, 4.18).
enum class ClipRule : uint8_t {
  kUnion,         // discard P if it is in at least one area
  kIntersection,  // discard P if it is in every area
};

// Eq. 4.13: N_cp is concave iff every partner sees M, the mean of the partners' centres:
// values (M - C_k)·n_k. centres, normals: #K each (unit normals); throws std::invalid_argument on
// a size mismatch. One partner gives kFlat (M = C_k).
Convexity partner_set_convexity(std::span<const Vec3f> centres, std::span<const Vec3f> normals,
                                double tol);

// Eq. 4.14: S ∪ N_cp is concave iff S sees every partner centre: values (C_k - C)·n.
Convexity splat_partner_convexity(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                                  double tol);

// Eq. 4.15 with the side standing for S ∪ N_cp (kBehind = concave, kFront = convex):
//   partners concave, behind -> union;         partners concave, front -> intersection;
//   partners convex,  behind -> intersection;  partners convex,  front -> union.
// Beyond the thesis: kFlat partners (all clip planes are one plane up to tol, or one partner) ->
// union, which then equals the intersection; kMixed partners -> intersection, the choice that
// discards less, so an unclassifiable corner keeps a sliver of overlap rather than a hole.
ClipRule clip_rule(Convexity partners, ClipSide side);

}  // namespace splatkit::graph
