// The values of a QSplat tree's nodes [Rusinkiewicz00], bottom up, once its shape is known: the
// second half of build_qsplat_tree, shared with merge_qsplat (which puts tiles' trees under new
// upper levels).
//
// Preconditions: t.level_begin, first_child and child_count give the shape (children
// consecutive, in the next level, 0 or 2..4 of them), t.leaf[i] names the leaf of each node
// without children (an index into `leaves`) and is kNoLeaf for the others. Fills t.spheres
// (leaves: their splat's sphere; interior nodes: enclose_spheres of the children's, or the
// centroid rule), t.normal_codes (interior: normalised sum of the children's normals), t.cones
// (interior: the largest angle between its decoded normal and any decoded normal below it),
// t.colors (interior: mean of the children's, when leaves have colours) and, with `measure`,
// the two mean interior radii of build_qsplat_tree.h. Deterministic for any thread count.
#pragma once

#include "qsplat/build_qsplat_tree.h"

namespace splatkit::qsplat {

void fit_qsplat_nodes(QSplatTree& t, const QSplatLeaves& leaves, bool centroid_rule, bool measure);

}  // namespace splatkit::qsplat
