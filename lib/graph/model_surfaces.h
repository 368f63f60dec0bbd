// model_surfaces: the geometry each surface of a segmentation is judged by (a plane, sphere or
// cylinder, fit_surface_primitive), after tidying the segmentation so that one surface is one
// primitive. The first half of refine_surface_borders.
//
//   1. Every surface of at least min_surface_size splats is fitted; the primitive *explains* it
//      when its robust residual scale is at most twice that of local planes through the
//      surface's own splats (each left out of its plane) plus a rounding floor (1e-5 of the
//      surface's extent), and 90 % of the splats lie within three scales. Primitives are fitted
//      to at most 4096 splats of the surface, evenly spread over its indices.
//   2. A surface nothing explains may be a union of primitives that leaked into one across a
//      crease (a hole and the face around it): when its primitive (the robust fit follows the
//      majority) holds at least half of its splats within its tolerance, the connected pieces
//      of the rest become surfaces of their own — kept only if every piece of at least
//      min_surface_size splats is explained in turn, or splits the same way (up to three levels);
//      otherwise the surface stays whole and *unexplained* (a free-form surface).
//   3. A surface that a larger adjacent surface's primitive explains for at least half of its
//      splats (of the one explaining most; ties: the larger, then the lower label) joins it at
//      once: its splats take that label (islands of one cylinder that the segmentation left
//      apart, a strip of wild normals along a crease).
// Surfaces under min_surface_size are fragments: no model.
//
// Deterministic for any thread count (fits in parallel per surface, decisions in label order).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "graph/fit_surface_primitive.h"
#include "graph/surface_borders.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct SurfaceModel {
  enum State : uint8_t { kFragment, kUnexplained, kPrimitive };
  State state = kFragment;
  SurfacePrimitive primitive;  // kPrimitive
  double tolerance = 0;        // kPrimitive: 3 robust scales, at least the rounding floor
};

struct SurfaceModels {
  std::vector<SurfaceModel> model;  // per label, 0 .. label_count - 1 (labels no splat has any
                                    // more are fragments)
  uint32_t joined = 0;              // surfaces that joined a neighbour (step 3)
  uint32_t split = 0;               // surfaces split into primitives (step 2)
};

// graph: symmetric neighbour rows; positions, normals: #N; label: #N values < label_count, changed
// in place (steps 2 and 3); label_count grows by the pieces of split surfaces (new labels from
// the old count up, in the order of each piece's lowest splat); borders: surface_borders of
// `label` on entry, of the changed labels on return. min_normal_dot: a splat counts as explained
// by a primitive only if n_i · (its normal there) >= this (NaN normals always do). O(N) for the
// fits, plus the rows of the border splats when surfaces join and a pass over every row when
// one splits; no check of the sizes (the caller's).
SurfaceModels model_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                             std::span<const Vec3f> normals, std::vector<uint32_t>& label,
                             uint32_t& label_count, SurfaceBorders& borders,
                             uint32_t min_surface_size, float min_normal_dot);

}  // namespace splatkit::graph
