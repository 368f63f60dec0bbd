// The QSplat bounding-sphere hierarchy over a set of leaves [Rusinkiewicz00], breadth first.
//
// Split: a range of more than 4 leaves is cut by rank along the longest axis of its centres'
// bounding box, and each half of more than C leaves again along the longest axis of its part of
// that box, giving 2–4
// children, each but the last two a complete subtree of C = 4^k leaves and the last two no
// smaller than C/2 (the original also cuts at ranks, choosing among them by volume; these ranks
// keep nodes at 4 children nearly everywhere, about 4/3 nodes per leaf, and no leaf alone under a
// large node). A range of 2–4 leaves becomes one node over those leaves, in input order, unless
// it holds 3–4 leaves and one of them is large (kPairLeavesAbove): then it is cut along its
// longest axis into a node of 2 leaves and the rest (a leaf, or a node of 2). Interior
// node: sphere around the child spheres (enclose_spheres.h; tight by default), normal = normalised
// sum of the children's normals, cone = the largest angle between its decoded normal and any
// decoded normal below it (so back-face culling with the decoded values is conservative), colour =
// mean of the children's. Deterministic: the same leaves give the same tree for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/qsplat_codes.h"
#include "qsplat/qsplat_leaves.h"
#include "splatkit/slot_array.h"

namespace splatkit::qsplat {

inline constexpr uint32_t kNoLeaf = 0xFFFFFFFFu;

// A node of 3 or 4 leaves one of which has a radius above this fraction of half the diagonal of
// the leaves' bounding box is split in two: a node of 2 leaves and one of the rest (a leaf or
// 2 leaves). A leaf's cell grid is 2/13 of its parent's radius; a pair's sphere is a third
// smaller than a group of four's, so large leaves, whose quantisation error shows in views of the
// whole model, get a finer grid, for one node more (formats/qsplat.md, "The tree splatkit builds").
inline constexpr double kPairLeavesAbove = 0.01;

struct QSplatTree {
  // Level l (0 = the root) holds nodes [level_begin[l], level_begin[l + 1]); #levels + 1 entries.
  std::vector<uint32_t> level_begin;
  std::vector<uint32_t> first_child;   // #M; children are consecutive, in the next level
  std::vector<uint8_t> child_count;    // #M; 0 for leaves, else 2..4
  SlotArray<uint32_t> leaf;            // #M index into the leaves, or kNoLeaf
  SlotArray<Sphere> spheres;           // #M true spheres (float; each contains its children's)
  SlotArray<uint16_t> normal_codes;    // #M (qsplat_codes.h)
  SlotArray<uint8_t> cones;            // #M cone codes
  SlotArray<uint16_t> colors;          // #M RGB 5-6-5, or none (size 0)
  // Mean radius of the interior nodes with the chosen rule, and with the centroid rule on the
  // same tree (for the report; 0 unless measured).
  double mean_interior_radius = 0, mean_interior_radius_centroid = 0;
  std::size_t size() const { return first_child.size(); }
  std::size_t levels() const { return level_begin.size() - 1; }
};

// Precondition: leaves.size() >= 2. `centroid_rule`: the original's spheres instead of tight ones.
// `measure`: also compute the two mean interior radii (costs a second sphere per node).
QSplatTree build_qsplat_tree(const QSplatLeaves& leaves, bool centroid_rule = false,
                             bool measure = true);

}  // namespace splatkit::qsplat
