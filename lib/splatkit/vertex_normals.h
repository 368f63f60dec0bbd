// vertex_normals: a mesh's normal at each vertex, the sum of the normals of the triangles around
// it weighted by their areas (polygons are fanned from their first vertex), so oriented as the
// faces wind (counter-clockwise seen from outside: outward).
#pragma once

#include <vector>

#include "splatkit/splat_cloud.h"
#include "splatkit/vec3.h"

namespace splatkit {

// #N unnormalised sums (twice the areas): zero at a vertex that no face of positive area uses.
// cloud.check_consistent() must hold (face indices in range).
std::vector<Vec3f> vertex_normals(const SplatCloud& cloud);

}  // namespace splatkit
