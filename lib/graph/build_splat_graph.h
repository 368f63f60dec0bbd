// The splat graph of [IvoMSc] ch. 3–4 (docs/references.md; section, table and equation numbers
// below are that thesis's): neighbour graph by bounding spheres, sharp and continuous edges,
// per-splat class ([Linsen01]), disc–disc crossings, clip partners and their classification, and
// the smooth surfaces (§5.4) used to group the partners. lib/graph/README.md has the decisions
// taken where the thesis is silent.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "graph/clip_record.h"
#include "graph/segment_surfaces.h"
#include "graph/segment_surfaces_robust.h"
#include "splatkit/progress.h"
#include "splatkit/spatial_index.h"
#include "splatkit/splat_cloud.h"

namespace splatkit::graph {

enum class SplatClass : uint8_t {
  kSmooth = 0,        // no sharp edge
  kEdge = 1,          // on a boundary of its smooth surface (a crease, a corner, an open border)
                      // next to another surface; its crossing sharp neighbours clip it
  kIntersection = 2,  // inside its smooth surface, which another surface crosses; never clipped
};
// A splat with a sharp edge is kEdge when
//   (a) Linsen's test (linsen_boundary_test over its continuous neighbours, gap > α) finds it on
//       a boundary — the test of §4.1; or, beyond the thesis,
//   (b) it has sharp neighbours whose discs cross its own, and for every such S_j all its
//       continuous neighbours' centres lie on one side of the line where the two planes meet
//       (none more than r_i / 4 beyond it, measured in S_i's plane): its surface stops at S_j
//       instead of passing through. Without (b) the second row of splats behind a crease, whose
//       discs still reach across it when splats overlap a lot (m ≈ 13), is surrounded by its own
//       surface, comes out as an "intersection" and is never clipped.
// Otherwise it is kIntersection.

// Per neighbour entry (parallel to NeighborGraph::neighbors; symmetric).
inline constexpr uint8_t kEdgeSharp = 1;     // w_ij = n_i·n_j < w_s (eq. 3.3; or not a number)
inline constexpr uint8_t kEdgeCrossing = 2;  // sharp, and the discs cross (§4.2)

struct SplatGraphOptions {
  float sharp_threshold = 0.9f;      // w_s: an edge is sharp iff n_i·n_j < w_s, in [-1, 1]
  double boundary_gap_degrees = 90;  // α of the Linsen test, in (0, 360]
  double flat_tolerance = 1e-3;      // convexity tolerance, as a fraction of the splat's radius
  bool per_surface = true;           // group clip partners by surface (false: one set per
                                     // splat as in the thesis, for comparison)
  // Surfaces: segment_surfaces_robust (true, default) or the thesis's components of the
  // continuous edges, segment_surfaces (false). robust: the robust method's core threshold (in
  // [-1, 1]; none: automatic) and min_core_size (>= 1); its sharp_threshold is the one above.
  bool robust_surfaces = true;
  RobustSegmentOptions robust;
  // false: SplatGraph::surfaces keeps the sizes (the count) but not the per-splat ids, which are
  // released once the clip partners are grouped (4 bytes per splat off the peak, for a caller
  // that does not write them).
  bool keep_surface_ids = true;
};

// The columns of [IvoMSc] tables 6.1–6.3. Edges are undirected pairs.
struct SplatGraphStats {
  uint64_t splats = 0;
  uint64_t edges = 0;
  double mean_degree = 0;  // m = 2 |E| / |V| (eq. 3.4)
  uint64_t sharp_edges = 0;
  uint64_t crossing_edges = 0;    // sharp edges whose discs cross: the real intersections
  uint64_t candidate_splats = 0;  // splats with at least one sharp edge
  uint64_t edge_splats = 0;       // class kEdge
  uint64_t intersection_splats = 0;
  uint64_t clipped_splats = 0;  // splats with at least one clip partner
  uint64_t clip_partners = 0;   // entries of the clip table
  uint32_t surfaces = 0;
  RobustSegmentInfo surface_method;  // robust surfaces: the noise seen and the core threshold
};

// Wall-clock seconds of the phases of build_splat_graph (for --report; not part of the result's
// identity: they vary from run to run).
struct SplatGraphTimings {
  double overlaps = 0;  // sphere_overlap_graph: the graph (eq. 3.1), its sharp edges (3.3)
  double classify = 0;  // crossing flags and classes of the splats with a sharp edge
  double surfaces = 0;  // segment_surfaces
  double clip = 0;      // the clip table and its classification
};

struct SplatGraph {
  NeighborGraph graph;              // E = {(i, j) : |C_i - C_j| < r_i + r_j} (eq. 3.1), built by
                                    // sphere_overlap_graph
  std::vector<uint8_t> edge_flags;  // kEdge* bits, parallel to graph.neighbors
  std::vector<SplatClass> classes;  // #N
  Segmentation surfaces;            // segment_surfaces_robust, or segment_surfaces
  ClipPartnerTable clip;            // partners of the kEdge splats; empty rows for the others
  SplatGraphStats stats;
  SplatGraphTimings timings;
};

// Elliptic splats (SplatCloud::axes, minor_radii; radii holds the larger semi-axis): both empty
// for circles. Disc–disc crossings then use the ellipses; the neighbour graph uses radii, the
// bounding spheres, either way.
struct SplatEllipses {
  std::span<const Vec3f> axes;
  std::span<const float> minor_radii;
};

// positions, normals (unit), radii (bounding-sphere radii): #N each, same frame; circles, or the
// ellipses given.
// Partners: for a kEdge splat S_i, every sharp neighbour S_j whose disc crosses S_i's (the test
// is always run with the lower index first, so it is symmetric); classified by
// classify_clip_partners with the partners' surface ids (options.per_surface) and tolerance
// flat_tolerance · r_i. Throws Error(kUsage) for options out of range, Error(kBadInput) for a
// NaN/infinite position or a radius that is negative or not finite, std::invalid_argument for
// arrays of different sizes. Runs in parallel with TBB; the result is identical for any thread
// count. Memory: about 5 bytes per neighbour entry plus ~40 bytes per splat.
SplatGraph build_splat_graph(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                             std::span<const float> radii, const SplatGraphOptions& options,
                             const ProgressFn& progress = no_progress(),
                             SplatEllipses ellipses = {});

// Same, for a cloud; Error(kBadInput) when it has no normals or no radii (run estimate-normals).
SplatGraph build_splat_graph(const SplatCloud& cloud, const SplatGraphOptions& options,
                             const ProgressFn& progress = no_progress());

// Same, with the cloud's positions, radii and normals lent to the neighbour graph while it is
// built (sphere_overlap_graph's LentSplats: 28 bytes per splat off the peak of memory). They hold
// the same values afterwards, also when it throws, in new buffers.
SplatGraph build_splat_graph_in_place(SplatCloud& cloud, const SplatGraphOptions& options,
                                      const ProgressFn& progress = no_progress());

}  // namespace splatkit::graph
