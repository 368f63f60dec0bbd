// The bytes of a QSplat .qs v11 file (formats/qsplat.md) for a tree: an optional comment fragment,
// then one tree fragment, big-endian, readable by the original QSplat viewer.
//
// Every child sphere is quantised against its parent's decoded sphere, and lies inside it: an
// interior node's with the conservative encode_sphere (qsplat_codes.h), whose decoded sphere
// contains the node's true sphere grown by kInteriorMargin (kLeafParentMargin over leaves), hence
// every splat below it (except a node over large leaves, kLeafGroupSearchAbove, whose cell is
// chosen for its leaves by choose_leaf_group_cell and contains its decoded leaves but not
// necessarily their splats); a leaf's with SphereEncoder::nearest_disc, the cell whose disc best
// matches the splat's (not conservative: a leaf is drawn as its disc, and a sphere grown to
// contain the splat rings every silhouette). Deterministic for any thread count (groups are
// placed by a prefix sum, then filled in parallel).
#pragma once

#include <string>
#include <vector>

#include "qsplat/build_qsplat_tree.h"

namespace splatkit::qsplat {

struct EncodedQSplat {
  std::vector<unsigned char> bytes;  // the whole file
  uint64_t tree_bytes = 0;           // the tree fragment's node groups and offsets
  uint64_t leaves = 0;
  // Decoded leaf radius over the leaf's true radius: mean and largest (what quantisation does to
  // the splats drawn at leaf level; below 1 where a leaf shrinks).
  double leaf_growth_mean = 0, leaf_growth_max = 0;
};

// The room an interior node's decoded sphere keeps around its true one: it must contain the true
// sphere grown by this fraction of its radius (the root too), so that children touching the true
// sphere (tight spheres always have two) still find small cells inside the decoded parent.
inline constexpr double kInteriorMargin = 0.25;
// The same for a node whose children are all leaves: none, since leaves take the cell nearest
// their disc inside the decoded parent (SphereEncoder::nearest_disc) and need no room around
// them; a tighter parent is a finer grid for its leaves.
inline constexpr double kLeafParentMargin = 0.0;
// A node whose children are all leaves and whose true radius exceeds this fraction of the root's
// (header) radius takes the cell choose_leaf_group_cell finds for its leaves instead (some
// hundred placements of its leaves tried): there a leaf grid step (2/13 of the node's radius) is
// half a pixel or more in a 720-pixel-high view of the whole model, and the search is paid only
// where leaves are large against the model (none in a dense 4M-splat torus; a third of the groups
// of the 100k-point building scan of docs/design/qsplat.md).
inline constexpr double kLeafGroupSearchAbove = 0.01;

// `comments`: text of the comment fragment (none when empty). Throws Error(kUnsupported) when the
// tree fragment would exceed 2^31 − 1 bytes (the format's int32 length; several fragments are
// not written), Error(kBadInput) when the splats span so wide a range that float32 steps exceed
// a node's radius and rounding leaves a node outside its decoded parent (a point 1e20 away from the
// rest may do that), Error(kInternal) when the tree's root has no grandchildren (fewer than 5
// leaves: callers refuse those first). On return tree.spheres holds the decoded spheres (the
// file's), which take the place of the true ones as the encoder goes down.
EncodedQSplat encode_qsplat(QSplatTree& tree, const std::string& comments);

}  // namespace splatkit::qsplat
