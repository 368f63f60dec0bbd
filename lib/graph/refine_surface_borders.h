// refine_surface_borders: moves the splats on the borders between surfaces, and the splats of
// fragments, to the adjacent surface whose fitted geometry explains them best. The step after
// segment_surfaces / segment_surfaces_robust that puts the border bands of noisy scans back where
// they belong (beyond [IvoMSc] §5.4; docs/references.md).
//
// A segmentation over the graph decides each splat by the normals along graph paths, so on a
// noisy scan the border between two surfaces lies a few splats off the true crease, on either
// side (the CAD part, 100 k random splats, noise 0.125 % of the bounding-box diagonal: IoU 0.936
// for its smallest patch). Geometry decides better. A pass:
//
//   1. model_surfaces fits each surface of at least min_surface_size splats with a plane, sphere
//      or cylinder, splits surfaces that are unions of them, joins surfaces a larger neighbour's
//      primitive explains, and marks what no primitive explains (free-form) as unexplained;
//      smaller surfaces are fragments, with no model.
//   2. Rounds: every border splat (one with a neighbour on another surface, or in a fragment) is
//      judged against the explained surfaces among itself and its neighbours whose primitive's
//      normal at the splat is compatible with its own (n_i · n_S >= min_normal_dot). The nearest
//      surface wins, except where two candidates meet at a crease whose convexity is clear and
//      the other candidate is within its noise (3 robust scales): at a convex crease a splat of
//      A lies inside B's half-space whatever its noise, so the larger signed distance wins; at a
//      concave one, the smaller (the rule the two surfaces' likelihoods give; nearest-only lost
//      1.7 % IoU on the CAD part). A crease is convex when each candidate's normal at the mean
//      position of its splats among the neighbours points away from the other's (by more than
//      crease_sine), concave when both point towards it; surfaces that cross are neither. A
//      splat next to an unexplained surface is left alone. All splats of a round are judged on
//      the labels the round started with, so the result does not depend on the order or the
//      thread count; later rounds judge only the splats that changed and their neighbours, and
//      rounds stop when nothing changes (or after `rounds`; a few splats can swap back and
//      forth).
// A pass that joined or split surfaces is followed by another (at most three in all).
//
// Splats that no explained surface takes keep their surface (fragments among them are for
// merge_small_surfaces). The result is renumbered in the order of each surface's lowest splat.
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct RefineBordersOptions {
  uint32_t rounds = 8;             // at most this many rounds of judging (0: return the input)
  uint32_t min_surface_size = 50;  // smaller surfaces are fragments: no model of their own
  float min_normal_dot = -0.5f;    // n_i · n_S a splat needs to join S: only surfaces that face
                                   // away by more than 120° are refused (near a crease the
                                   // estimated normals are wrong by tens of degrees)
  double crease_sine = 0.17;       // |n · direction| beyond which a crease's convexity counts
                                   // (sin 10°)
};

// What the refinement saw and did.
struct RefineBordersInfo {
  uint32_t planes = 0, spheres = 0, cylinders = 0;  // surfaces explained by each (last pass)
  uint32_t unexplained = 0;  // surfaces of at least min_surface_size nothing explains
  uint32_t joined = 0;       // surfaces that joined a larger neighbour explaining them
  uint32_t split = 0;        // surfaces split into the primitives they were made of
  uint32_t passes = 0;       // passes of fitting and judging
  uint32_t rounds = 0;       // rounds of judging, over all passes
  uint64_t moved = 0;        // splat moves, over all rounds
};

// graph: symmetric neighbour rows; positions, normals: #N each (NaN normals are accepted: such a
// splat is judged by position alone); segmentation: #N ids < count(). Throws
// std::invalid_argument on size mismatch or an id out of range. Deterministic for any thread
// count. Time: the fits are O(N) (each primitive on at most 4096 of its surface's splats), a
// round O(rows of the judged splats).
Segmentation refine_surface_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                    std::span<const Vec3f> normals, Segmentation segmentation,
                                    const RefineBordersOptions& options,
                                    RefineBordersInfo* info = nullptr);

}  // namespace splatkit::graph
