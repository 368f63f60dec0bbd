// The per-splat clip record: written by build_splat_graph, read by splat-view ([IvoMSc]
// §4.3–§4.4, eqs. 4.15–4.18, in docs/references.md; extended per surface as lib/graph/README.md
// describes). Header-only: the fragment test runs per pixel.
//
// A splat S with clip partners N_cp has its partners grouped in subsets, one per surface id of
// the partners (one subset when no surface ids are known: the method of [IvoMSc]). Each subset k
// has its rule R_k (union or intersection of its partners' areas); the splat has a combine rule R
// across the subsets. Each partner j has a side: its clip area is {P : (P - C_j)·n_j > 0} (front)
// or {P : (P - C_j)·n_j < 0} (behind) (eq. 4.17). A fragment at P is discarded iff
//     R over subsets k of ( R_k over partners j in k of [P in area_j] )
// with union = "at least one", intersection = "all" (eq. 4.18). A splat without partners is never
// clipped. How the rules are chosen: classify_clip_partners.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splatkit/vec3.h"

namespace splatkit::graph {

// Per-partner flag bits.
inline constexpr uint8_t kClipFront = 1;               // area (P - C_j)·n_j > 0; clear: < 0
inline constexpr uint8_t kClipSubsetStart = 2;         // first partner of a subset
inline constexpr uint8_t kClipSubsetIntersection = 4;  // on a subset's first partner: the
                                                       // subset's areas combine by intersection
                                                       // (clear: union)
inline constexpr uint8_t kClipPartnerFlagsKnown = 7;
// Per-splat flag bits.
inline constexpr uint8_t kClipCombineIntersection = 1;  // subsets combine by intersection
                                                        // (clear: union); moot with one subset
inline constexpr uint8_t kClipSplatFlagsKnown = 1;

// The stored form (writer: build_splat_graph; reader: splat-view), compressed rows over splats.
// The partners of splat i are partners[offsets[i] .. offsets[i + 1]), grouped by subset in
// ascending surface id, ascending splat index within a subset; flags is parallel to partners
// and the first partner of every non-empty row has kClipSubsetStart. Sizes: offsets #N + 1
// (offsets[0] = 0, non-decreasing), partners and flags #P < 2^32, splat_flags #N. Memory: 5
// bytes per partner + 5 per splat.
inline constexpr uint64_t kMaxClipPartners = 0xFFFFFFFFu;
struct ClipPartnerTable {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> partners;
  std::vector<uint8_t> flags;
  std::vector<uint8_t> splat_flags;

  std::size_t num_splats() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  bool has_partners(std::size_t i) const { return offsets[i + 1] != offsets[i]; }
  std::size_t clipped_splats() const {  // splats with at least one partner
    std::size_t count = 0;
    for (std::size_t i = 0; i < num_splats(); ++i) count += has_partners(i);
    return count;
  }
  // Throws std::logic_error naming the first violation of the layout above (sizes, offsets,
  // partner index >= num_splats() or == its own splat, unknown flag bits, a row that does not
  // start a subset).
  void check_consistent() const;
};

// The render-time form of one partner: P is in its clip area iff dot(m, P) > e. The side is
// folded in: front m = n_j, e = n_j·C_j; behind m = -n_j, e = -n_j·C_j (16 bytes).
struct ClipPlane {
  Vec3f m;
  float e = 0;
};

// One splat's clip data as the fragment test reads it (see make_clip_planes.h for building it).
struct ClipView {
  const ClipPlane* planes = nullptr;
  const uint8_t* flags = nullptr;  // kClip* partner bits, parallel to planes
  uint32_t count = 0;
  bool combine_intersection = false;
};

// The plane of partner (c_j, n_j) with its side (flags & kClipFront).
inline ClipPlane make_clip_plane(const Vec3f& c_j, const Vec3f& n_j, uint8_t flags) {
  const Vec3f m = (flags & kClipFront) ? n_j : -n_j;
  return {m, dot(m, c_j)};
}

inline bool in_clip_area(const ClipPlane& plane, const Vec3f& p) {
  return dot(plane.m, p) > plane.e;
}

// Eq. 4.18 per subset, then the combine rule: true iff the fragment at p (same frame as the splat
// centres) must be discarded. O(count), no allocation, no branch on anything but the flags.
inline bool fragment_discarded(const ClipView& view, const Vec3f& p) {
  if (view.count == 0) return false;
  bool any = false, all = true;
  uint32_t k = 0;
  while (k < view.count) {
    const bool intersection = (view.flags[k] & kClipSubsetIntersection) != 0;
    bool subset = intersection;
    do {
      const bool in = in_clip_area(view.planes[k], p);
      subset = intersection ? (subset && in) : (subset || in);
      ++k;
    } while (k < view.count && (view.flags[k] & kClipSubsetStart) == 0);
    any = any || subset;
    all = all && subset;
  }
  return view.combine_intersection ? all : any;
}

}  // namespace splatkit::graph
