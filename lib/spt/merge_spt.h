// One Sequential Point Tree list [Dachsbacher03] from the lists of several tiles (formats/spt.md;
// docs/design/tiles.md, "Merged LOD files").
//
// Each tile's list holds one tree whose root is the entry with r_max = infinity. The merged tree
// keeps every tile's entries and puts new interior discs above the tiles' roots: the roots are
// put in Morton order over the cube of all entries (sort_spt_splats) and cut where their codes
// part, as build_spt_tree cuts splats, and each new node is the disc fitted to its children
// (fit_spt_disc), its error made monotone over theirs. A tile root's r_max becomes its new parent's
// r_min; every other interval is the tile's own, re-quantised on the merged file's scales. Since a
// child's r_max and its parent's r_min decode to the same float in the tile's file, they take the
// same code again: the cut property holds for the merged list as for each tile's.
//
// Tiles built in the survey's Morton cube and frame (build-spt over splat-tile's survey box;
// formats/tiles.md) share one quantisation frame, the merged one: their positions keep their
// codes and the discs are not grown again, and each tile's subtree of a Morton cell inside the
// tile is the whole build's; a tile whose root cell is such a cell is grouped with the others as
// the whole build groups those cells (their centres' codes part where the cells do).
//
// What the merged list loses against a list built over all the splats at once: r values are
// quantised twice on logarithmic scales (the tile's, then the merged one: relative error ≤ 1e-4
// each; an interval that one scale makes empty and the other does not is dropped or kept
// accordingly), a tile root's colour deviation is not stored, so the new nodes' colour term counts
// only their own children's spread, and the nodes of Morton cells across the tiles' borders are
// the tiles' (each over its part of the cell). Tiles built in their own frames (no survey box)
// also lose a second rounding of positions (error ≤ the half steps of both frames; the discs grown
// by the merged half step again, so they still cover the true discs) and their trees are those of
// their own cubes, whose cells are not the whole build's.
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
