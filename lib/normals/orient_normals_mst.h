// orient_normals_mst: consistent normal orientation by propagation over a minimum spanning tree of
// the kNN graph (Hoppe, DeRose, Duchamp, McDonald, Stuetzle 1992; SPEC §1), `estimate-normals
// --orient mst`.
//
// Graph: every point joined to its k - 1 nearest neighbours (undirected). Weight of an edge
// 1 − |g_i·g_j| over the guide normals g, so the tree follows directions that agree and avoids
// jumps; weights are quantised to kOrientBuckets levels of sqrt(1 − |g_i·g_j|) (finer where
// normals nearly agree) and sorted by counting sort, ties broken by edge order (point index, then
// neighbour rank); the minimum spanning forest is built by Kruskal with union-find. Propagation
// flips g_j when g_i·g_j < 0 along each tree edge, breadth-first from each component's seed.
//
// Outward sign, per connected component: the component's point of largest z (smallest index on
// ties) is made to point +z (its normal's z >= 0). For a closed surface that point is a top-most
// point, where the outward normal has z > 0, so the whole component ends up pointing outward. Open
// sheets seen from above (terrain, facades' tops) point up.
//
// Guide: with PCA normals as the guide and robust (crease-sharp) normals as the output, the tree
// sees a field that turns smoothly over each crease instead of jumping by up to 120° (where the
// sign rule fails: across a 90° crease n_i·n_j ≈ 0 decides nothing). Each output normal then takes
// the sign that agrees with its oriented guide. Without a guide, the normals are their own guide.
//
// Memory: 8 bytes per graph edge for the neighbour rows and their keys, 4 per edge for the sorted
// order, 12 per point for the forest: about 12 k + 20 bytes per point at peak (k = 10: 140).
// Time: one kNN pass, a counting sort and a near-linear union-find. Deterministic for any thread
// count (the kNN rows are exact; everything after them is sequential).
#pragma once

#include <cstddef>
#include <span>

#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

inline constexpr std::size_t kOrientK = 10;  // kNN row length, the point itself included
inline constexpr std::size_t kOrientBuckets = 4096;

struct OrientStats {
  std::size_t flipped = 0;     // output normals whose sign changed
  std::size_t components = 0;  // connected components of the kNN graph (isolated points count)
};

// index: built over positions (#N). normals: #N unit normals, re-signed in place. guide: empty or
// #N unit normals (see above). k >= 2 (else std::invalid_argument).
OrientStats orient_normals_mst(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::span<const Vec3f> guide = {},
                               std::size_t k = kOrientK);

}  // namespace splatkit
