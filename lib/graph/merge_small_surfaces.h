// merge_small_surfaces: every surface with fewer than `min_size` splats (a fragment) joins the
// neighbouring surface it shares the most graph edges with.
//
// Fragments are taken smallest first (ties: lower id), each joining the neighbour with the most
// edges from its splats (any edge, sharp or not; ties: the larger neighbour, then the lower id);
// a fragment may join another fragment, and the pair is taken again in the next pass if it is
// still under min_size. Passes repeat until no fragment can join anything. A fragment with no
// edge to another surface (an isolated cluster) then joins, when `splats` are given, the surface
// of the nearest splat outside it if that one nearly touches it: centres less than twice the
// two radii apart (a stray that noise lifted off its surface, whose sphere just misses its
// neighbours'); a cluster farther from everything (a small separate object) stays on its own. The
// result is renumbered in the order of each surface's lowest splat index (renumber_surfaces), so
// it is deterministic.
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"

namespace splatkit::graph {

// graph: symmetric neighbour rows; segmentation: ids < count() for every splat (no kNoSurface),
// graph.num_points() of them (std::invalid_argument otherwise). min_size <= 1: nothing merges
// (only the renumbering). O(splats of fragments × row length) per pass, plus O(N).
// splats: the positions and radii (#N each), or empty (isolated clusters stay).
struct SplatSpheres {
  std::span<const Vec3f> positions;
  std::span<const float> radii;
};
Segmentation merge_small_surfaces(const NeighborGraph& graph, Segmentation segmentation,
                                  uint32_t min_size, SplatSpheres splats = {});

}  // namespace splatkit::graph
