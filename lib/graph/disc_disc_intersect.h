// Do two splats cross? ([IvoMSc] §4.2 in docs/references.md: plane line eqs. 4.4–4.7, chords
// eqs. 4.11/4.12, overlap §4.2.3)
#pragma once

#include "graph/geometry_types.h"

namespace splatkit::graph {

enum class DiscCrossing {
  kCross,     // both chords exist and overlap: the splats cut each other; they are clip partners
  kParallel,  // the planes are parallel or coincident (no line; see plane_plane_line)
  kMissI,     // the line misses splat i
  kMissJ,     // the line misses splat j
  kDisjoint,  // both chords exist but do not overlap: side by side, a false positive (fig. 4.2a)
};

struct DiscDiscResult {
  DiscCrossing status = DiscCrossing::kParallel;
  Line3 line;          // valid unless kParallel
  Interval segment_i;  // valid when status is kCross, kMissJ or kDisjoint
  Interval segment_j;  // valid when status is kCross or kDisjoint
  Interval overlap;    // valid when kCross: [max(t0), min(t1)], the common piece of the chords

  bool crosses() const { return status == DiscCrossing::kCross; }
};

// Intersects splats s_i and s_j (circles or ellipses, see SplatDisc; unit normals). The chords
// are closed intervals of the line's parameter, and the splats cross iff they are not disjoint
// ([IvoMSc] §4.2.3: "não forem disjuntos", are not disjoint): chords that touch at one point count
// as crossing. Swapping i and j gives the same line with its direction reversed (t negated), hence
// the same answer up to rounding; callers that need bit-identical results (build_splat_graph)
// always pass the lower splat index as i.
DiscDiscResult disc_disc_intersect(const SplatDisc& s_i, const SplatDisc& s_j,
                                   double min_sin2 = 1e-12);

}  // namespace splatkit::graph
