// vertex_normals: a mesh's normal at each vertex, the sum of the normals of the triangles around
// it weighted by their areas (polygons are fanned from their first vertex), so oriented as the
// faces wind (counter-clockwise seen from outside: outward).
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
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

// Calls fn(t, lo, hi) for every triangle t of the mesh with a vertex in [lo, hi), for ranges
// [lo, hi) that split the vertices among tasks run in parallel, one per thread of the arena: fn
// writes only the entries of vertices in [lo, hi). Every task reads all the faces (cheap beside
// what fn does) and sees its triangles in face order, so a per-vertex sum comes out as a single
// pass over the faces makes it, whatever the thread count.
template <class Fn>
void for_each_triangle_by_vertex_range(const SplatCloud& cloud, Fn&& fn) {
  const std::size_t n = cloud.size();
  const auto tasks = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t task) {
    const auto lo = static_cast<uint32_t>(n * task / tasks),
               hi = static_cast<uint32_t>(n * (task + 1) / tasks);
    for_each_triangle(cloud, [&](const std::array<uint32_t, 3>& t) {
      if ((t[0] >= lo && t[0] < hi) || (t[1] >= lo && t[1] < hi) || (t[2] >= lo && t[2] < hi))
        fn(t, lo, hi);
    });
  });
}

// #N unnormalised sums (twice the areas): zero at a vertex that no face of positive area uses.
// cloud.check_consistent() must hold (face indices in range). In parallel, the same sums for any
// thread count (for_each_triangle_by_vertex_range).
std::vector<Vec3f> vertex_normals(const SplatCloud& cloud);

}  // namespace splatkit
