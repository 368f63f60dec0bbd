// One QSplat tree [Rusinkiewicz00] from the .qs trees of several tiles (formats/qsplat.md;
// docs/design/tiles.md, "Merged LOD files").
//
// The tiles' roots are clustered as build_qsplat_tree clusters splats (cut by rank along the
// longest axis, 2–4 children a node), and each cluster leaf is replaced by that tile's tree: its
// shape as in the tile's file, its leaves the tile's decoded leaves (centre, radius, normal,
// colour). QSplat stores each sphere relative to its decoded parent, so a subtree cannot be
// copied under a new parent: every node is fitted again bottom up over the decoded leaves
// (fit_qsplat_nodes: tight spheres, normals, cones, colours) and the whole tree is quantised again
// by encode_qsplat. What that costs: each leaf is quantised twice (its tile's cell, then the
// merged tree's cell nearest that cell's disc), and an interior node's sphere encloses its
// children's decoded discs instead of the splats. A tile root with one child (the original's
// files may have one) is replaced by that child.
//
// Deterministic: the same files in the same order give the same tree, for any thread count.
#pragma once

#include <array>
#include <span>
#include <string>

#include "formats/read_qsplat.h"
#include "qsplat/build_qsplat_tree.h"

namespace splatkit::qsplat {

struct MergedQSplatTree {
  QSplatTree tree;                        // fitted, ready for encode_qsplat
  uint64_t leaves = 0;                    // the tiles' leaves, all kept
  uint32_t upper_nodes = 0;               // nodes above the tiles' roots
  std::array<double, 3> origin{0, 0, 0};  // of the tree's frame (common_origin of the tiles')
};

// Refuses, with Error(kBadInput) "<name>: <cause>" naming the file, a file of more than one tree
// fragment and tiles that differ from the first in colour. Tiles of other origins (qsplat_origin;
// splat-tile gives a tile far from the survey's origin its own) are moved into the frame of the
// origin most of them share (common_origin.h).
// Precondition: names.size() == tiles.size() >= 1.
MergedQSplatTree merge_qsplat_tree(std::span<const QSplatModel> tiles,
                                   std::span<const std::string> names);

}  // namespace splatkit::qsplat
