// One Sequential Point Tree list [Dachsbacher03] from the lists of several tiles (formats/spt.md;
// docs/design/tiles.md, "Merged LOD files").
//
// Each tile's list holds one tree whose root is the entry with r_max = infinity. The merged tree
// keeps every tile's entries and puts new interior discs above the tiles' roots: the roots are
// put in Morton order (sort_spt_splats) and cut where their codes part, as build_spt_tree cuts
// splats, and each new node is the disc fitted to its children (fit_spt_disc), its error made
// monotone over theirs. A tile root's r_max becomes its new parent's r_min; every other interval
// is the tile's own, re-quantised on the merged file's scales. Since a child's r_max and its
// parent's r_min decode to the same float in the tile's file, they take the same code again: the
// cut property holds for the merged list as for each tile's.
//
// What the merged list loses against a list built over all the splats at once: positions are
// quantised twice (the tile's frame, then the merged one: error ≤ the half steps of both; the
// discs are grown by the merged half step again, so they still cover the true discs), r values
// twice on logarithmic scales (relative error ≤ 1e-4 each), and a tile root's colour deviation is
// not stored, so the new nodes' colour term counts only their own children's spread. The trees
// below the tiles' roots are the tiles' (cut at the tiles' borders), not the whole survey's.
//
// Deterministic: the same lists give the same bytes in any order (tiles are taken in the Morton
// order of their roots, ties by their order in `tiles`).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/read_spt.h"

namespace splatkit::spt {

struct MergedSpt {
  std::vector<unsigned char> bytes;  // the whole .spt file
  uint64_t entries = 0;
  uint64_t dropped_empty = 0;  // entries whose interval became empty (r_min = r_max codes)
  uint64_t new_nodes = 0;      // interior discs above the tiles' roots
  uint32_t depth = 0;
};

// The tiles must agree on precision, colour, epsilon and colour weight, and each must hold
// one tree (exactly one entry with r_max = infinity); otherwise Error(kBadInput)
// "<name>: <cause>" naming the file (names[i] names tiles[i]). Precondition: names.size() ==
// tiles.size() >= 1.
// Tiles of other origins (splat-tile gives a tile far from the survey's origin its own) are moved
// into the frame of the origin most of them share (ties: the smallest), which the merged list
// keeps.
MergedSpt merge_spt(std::span<const SptModel> tiles, std::span<const std::string> names);

}  // namespace splatkit::spt
