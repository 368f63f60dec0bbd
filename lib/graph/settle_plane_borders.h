// settle_plane_borders: splats on the border between two planar surfaces go to the one whose
// plane they lie nearer — the last step of segment-surfaces (beyond [IvoMSc] §5.4,
// docs/references.md).
//
// Where two faces meet at a shallow crease (a gable on a roof, 40 degrees from it) the estimated
// normals blend from one to the other over a band a few splats wide, and the segmentation leaves
// that band with whichever face its normals reached first; merge_coplanar_surfaces then holds it
// within the larger face's noise. The faces' fitted planes tell better: a splat of the band is
// nearer the plane of the face it belongs to (the least-squares assignment of k-plane
// clustering, Bradley and Mangasarian 2000, restricted to the border). Each surface of at least
// min_size splats gets a robust plane (fit_robust_plane); a splat of a planar surface A with a
// graph neighbour on a planar surface B moves to B when it is nearer B's plane than A's and B's
// plane holds it (within offset_scales of B's scale). Of several such B, the nearest plane wins
// (ties: the lower id). Rounds judge every splat on the labels of the round's start (the same
// result for any thread count and order); after the first, only the splats that changed and
// their neighbours are judged; at most `rounds` rounds. The planes are not refitted. The result
// is renumbered in the order of each surface's lowest splat (renumber_surfaces).
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct SettlePlaneBordersOptions {
  double offset_scales = 3;        // a plane holds the splats within this many of its scales
                                   // (0: nothing moves)
  double max_normal_degrees = 25;  // median angle of a planar surface's normals from its plane
  double min_crease_degrees = 30;  // planes nearer parallel than this are left alone (a relief
                                   // step, not a crease: distance does not tell them apart)
  bool crease_side = true;         // also move splats within their own plane's noise that lie
                                   // on the other face's side of the crease
  uint32_t rounds = 8;             // at most this many rounds
  uint32_t min_size = 50;          // smaller surfaces are not fitted; their splats stay
};

// graph: symmetric neighbour rows; positions, normals, radii: #N each; segmentation: #N ids <
// count(). Throws std::invalid_argument on a size mismatch or an id out of range. `moved`, when
// given, receives the number of splat moves. O(N) for the fits plus O(border rows) per round.
Segmentation settle_plane_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                  std::span<const Vec3f> normals, std::span<const float> radii,
                                  Segmentation segmentation,
                                  const SettlePlaneBordersOptions& options,
                                  uint64_t* moved = nullptr);

}  // namespace splatkit::graph
