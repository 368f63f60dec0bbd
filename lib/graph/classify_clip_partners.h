// Classify a splat's clip partners and choose its clip rules: [IvoMSc] §4.3 eqs. 4.13–4.15
// (docs/references.md), and beyond the thesis (its §7.3) per surface, for corners where the
// partners come from several surfaces. Output: the flags of the clip record (clip_record.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "graph/convexity.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct ClipSubsetInfo {
  uint32_t surface = 0;                   // the partners' surface id (0 when none were given)
  uint32_t begin = 0, end = 0;            // its partners' positions in ClipClassification::order
  Convexity partners = Convexity::kFlat;  // eq. 4.13 over this subset
  Convexity splat = Convexity::kFlat;     // eq. 4.14: S with this subset
  ClipRule rule = ClipRule::kUnion;       // how this subset's areas combine
};

struct ClipClassification {
  std::vector<uint32_t> order;        // #K: order[k] = input position of the partner stored k-th
  std::vector<uint8_t> flags;         // #K, stored order: kClipFront, kClipSubsetStart,
                                      // kClipSubsetIntersection (see clip_record.h)
  bool combine_intersection = false;  // across subsets (false with one subset)
  Convexity subsets_convexity = Convexity::kFlat;  // eq. 4.13 over the subsets' representatives
  std::vector<ClipSubsetInfo> subsets;             // ascending surface id
};

// c, n: the splat S (unit normal). centres, normals: its K clip partners (unit normals).
// surfaces: the partners' surface ids (#K), or empty for "all one surface" — exactly the thesis's
// method. tol: the flatness tolerance of convexity.h, a length (build_splat_graph uses 1e-3 r_S).
// Throws std::invalid_argument when the sizes differ.
//
// 1. Partners are grouped by surface id (stable: input order within a subset).
// 2. Per subset: eqs. 4.13 and 4.14. All partners of a subset share one side: the subset's
//    S ∪ N class (concave -> behind, convex -> front, eq. 4.17); when that is kFlat or kMixed, the
//    sign of the symmetric crease test on the subset's mean centre M and normalised mean normal
//    N, (M - C)·(n - N) (> 0: concave, behind; else front). The subset's rule is
//    clip_rule(class by eq. 4.13, side), eq. 4.15.
// 3. Across subsets (when there are two or more), a fragment must be tested against the surfaces
//    as the solid is built from them:
//    - if S sees some surfaces and not others (sides differ), union: a point of S's plane is
//      wrong if it is inside the solid behind a surface S sees OR in the air beyond a surface S
//      does not see. Example: S on a box's side face near the floor and near another side face.
//    - otherwise every subset is reduced to one representative (mean centre, normalised mean
//      normal) and the representatives are classified like partners: eq. 4.13 then eq. 4.15 with
//      the common side. Cube corner, S on face A, partners on B and C (S sees neither; B, C convex)
//      -> union: discard what lies beyond B's plane or beyond C's. S on the floor next to a box's
//      vertical edge (sees both faces, convex pair) -> intersection: discard only what is inside
//      the box (behind both faces); a plain "any subset discards" would cut holes into the floor.
void classify_clip_partners(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                            std::span<const Vec3f> normals, std::span<const uint32_t> surfaces,
                            double tol, ClipClassification& out);

}  // namespace splatkit::graph
