// vertex_normals: a mesh's normal at each vertex, the sum of the normals of the triangles around
// it weighted by their areas (polygons are fanned from their first vertex), so oriented as the
// faces wind (counter-clockwise seen from outside: outward).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "splatkit/splat_cloud.h"
#include "splatkit/vec3.h"

namespace splatkit {

// Calls fn({a, b, c}) for every triangle of the mesh's faces, polygons fanned from their first
// vertex (a face of fewer than 3 vertices has none). cloud.check_consistent() must hold.
template <class Fn>
void for_each_triangle(const SplatCloud& cloud, Fn&& fn) {
  for (std::size_t f = 0; f < cloud.face_count(); ++f) {
    const uint32_t b = cloud.face_offsets[f], e = cloud.face_offsets[f + 1];
    for (uint32_t k = b + 1; k + 1 < e; ++k)
      fn(std::array<uint32_t, 3>{cloud.face_indices[b], cloud.face_indices[k],
                                 cloud.face_indices[k + 1]});
  }
}

// #N unnormalised sums (twice the areas): zero at a vertex that no face of positive area uses.
// cloud.check_consistent() must hold (face indices in range).
std::vector<Vec3f> vertex_normals(const SplatCloud& cloud);

}  // namespace splatkit
