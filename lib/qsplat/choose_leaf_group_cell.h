// The sphere cell of a QSplat node whose children are all leaves, chosen for its leaves' sake
// (formats/qsplat.md, "The quantisers"; docs/design/qsplat.md, "Leaf groups").
//
// A leaf's cell is one of the 7621 cells of its parent's decoded sphere: a grid whose step is
// 2/13 of that sphere's radius, so where the parent's decoded sphere sits decides how near each
// leaf's cell can come to its splat. Instead of the smallest cell of the grandparent that
// contains the node's true sphere (encode_sphere), this tries every cell of the grandparent whose
// radius lies within [kLeafGroupRadiusLow, kLeafGroupRadiusHigh] times the node's true radius and
// whose centre lies within kLeafGroupCentreReach of it (and the containing cell too), places each
// leaf in it with SphereEncoder::nearest_disc, and keeps the cell of least
//   sum over the leaves of  r · (|c' − c| + |r' − r|)
// (r, c the splat's radius and centre, r', c' its decoded leaf's): a displaced or resized disc
// moves its edge in the image, over a length that grows with its radius. Ties keep the
// containing cell, then the first in table order. The cell found need not contain the leaves'
// splats (its leaves' decoded spheres lie inside it, which is what culling needs). Deterministic.
#pragma once

#include <cstdint>

#include "formats/qsplat_codes.h"

namespace splatkit::qsplat {

// The search range, in units of the node's true radius.
inline constexpr double kLeafGroupRadiusLow = 0.7, kLeafGroupRadiusHigh = 2.2;
inline constexpr double kLeafGroupCentreReach = 0.6;
// The weight of a leaf's bare band against its grown band in the group's cost (nearest_disc
// weighs it kBareWeight = 3 when it places one leaf): with 3 the leaves of a group grow, and the
// silhouettes of a scan's large splats with them; with 1, bare bands open single pixels where one
// splat alone covers the surface (docs/design/qsplat.md, "Leaf groups").
inline constexpr double kLeafGroupBareWeight = 1.5;

// `grandparent`: the decoded sphere the node is quantised in (its encoder `encode`); `tight`: the
// node's true sphere; `containing`/`containing_code`: the cell encode_sphere chose (the first
// candidate); `leaves`: #count (2..4) true leaf spheres, `normal_codes` their 14-bit codes.
// Returns the chosen code; `decoded` gets its sphere.
int choose_leaf_group_cell(const Sphere& grandparent, const Sphere& tight, int containing_code,
                           const Sphere& containing, const Sphere* leaves,
                           const uint16_t* normal_codes, int count, Sphere* decoded);

}  // namespace splatkit::qsplat
