// A sphere around 1..4 spheres, the bounding sphere of a QSplat interior node.
#pragma once

#include "formats/qsplat_codes.h"

namespace splatkit::qsplat {

// Tight rule (default): the smallest sphere around the pair that reaches farthest apart, when it
// holds the others within 1e-6 of its radius (then no sphere around them all is smaller by more
// than that, and the other candidates are not tried); else the smallest of the candidate spheres
// centred there, at the centroid and at the centre of the spheres' bounding box. Each
// candidate's radius is max |c − c_i| + r_i, so whichever wins encloses every sphere. Centroid
// rule (the original QSplat's): centre = mean of the centres, radius = max |c − c_i| + r_i. Either
// way the radius is evaluated in double on the float centre and rounded up, so that the float
// sphere contains every float child sphere (what the conservative quantiser relies on).
Sphere enclose_spheres(const Sphere* s, int count, bool centroid_rule = false);

}  // namespace splatkit::qsplat
