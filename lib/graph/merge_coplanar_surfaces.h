// merge_coplanar_surfaces: adjacent surfaces that lie on one plane become one surface — the last
// step of segment-surfaces (beyond [IvoMSc] §5.4, docs/references.md).
//
// On a photogrammetry scan a facade is one plane with relief (window reveals, sills, pilasters)
// and noisy normals that flip in places; the segmentation and the border refinement, which
// decide by normals along graph paths and by how well a primitive explains a surface, leave it
// in many pieces, some tilted against the facade or a few decimetres in front of it, and a
// fitted plane "explains" none of them (the relief puts more than 10 % of the splats beyond three
// noise scales). Here each surface of at least min_size splats gets a robust plane
// (fit_robust_plane: its scale is the surface's noise and relief about the plane; planar when
// its normals scatter about the plane's rather than turn away from it). Surfaces are joined
// into groups, each judged by its plane: with refit_groups the robust plane of all its splats
// (refitted once the group has grown by a tenth), else its largest surface's (its anchor's):
//   - two groups that share a graph edge join when the larger's plane is planar, the two planes
//     are within max_angle_degrees (either sign) and the smaller lies on the larger's plane: the
//     median distance of its splats from it is within offset_scales of the plane's scales, or
//     one splat diameter (a step lower than the splats are wide is below what the sampling
//     resolves); or, when the smaller has at most half the larger's splats (a bay or a pilaster
//     is the facade's relief), within relief_scales of the plane fitted to both together (the
//     cut of the biweight that fits it: the fit still weighs splats there as its own); or when
//     each lies within the other's relief_scales (two like halves of one facade; two planes
//     whose offset is beyond either's relief stay apart). Passes over the pairs repeat until
//     none joins;
//   - with join_disjoint, two planar groups that share no edge join when their planes are within
//     max_disjoint_degrees and each lies on the other's plane (the two wings of a facade either
//     side of a recessed middle are one plane), or the smaller, at most half the larger, lies
//     within relief_scales of the plane fitted to both.
// Parallel faces at a step higher than that, and faces that meet at a crease, stay apart. Pairs
// are taken largest first (by the larger surface's size, then the smaller's, then the ids), so
// the result is deterministic for any thread count; it is renumbered in the order of each
// surface's lowest splat (renumber_surfaces).
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct CoplanarMergeOptions {
  double offset_scales = 3;          // how far (in the anchor's scales) a surface it takes lies,
                                     // as a median (0: nothing joins)
  double relief_scales = 4.685;      // a group at most half the larger's size, or one each of
                                     // two lies within, may lie this far (fit_robust_plane's
                                     // biweight cut; at most offset_scales: off)
  double max_normal_degrees = 25;    // median angle of a planar surface's normals from its plane
  double max_angle_degrees = 30;     // between the planes of two adjacent anchors that join
  bool join_disjoint = true;         // also join groups that share no edge but lie on one plane
  double max_disjoint_degrees = 10;  // between the planes of two such anchors
  bool refit_groups = true;          // judge a group by the plane of all its splats, not its
                                     // largest surface's
  uint32_t min_size = 50;            // smaller surfaces are not fitted and do not join here
};

struct CoplanarMergeInfo {
  uint32_t planar = 0;    // surfaces found planar
  uint32_t joined = 0;    // surfaces that joined another
  uint32_t disjoint = 0;  // of which groups that share no edge with the one they joined
};

// graph: symmetric neighbour rows; positions, normals: #N each (NaN normals are left out of the
// planarity test); segmentation: #N ids < count(). Throws std::invalid_argument on a size
// mismatch or an id out of range. O(N) for the fits plus O(E) for the adjacent pairs.
Segmentation merge_coplanar_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                     std::span<const Vec3f> normals, std::span<const float> radii,
                                     Segmentation segmentation, const CoplanarMergeOptions& options,
                                     CoplanarMergeInfo* info = nullptr);

}  // namespace splatkit::graph
