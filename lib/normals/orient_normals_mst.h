// orient_normals_mst: consistent normal orientation over the kNN graph, `estimate-normals
// --orient mst`: smooth sheets grown as Hoppe's minimum spanning tree grows them (Hoppe, DeRose,
// Duchamp, McDonald, Stuetzle 1992: [Hoppe92] in docs/references.md), then joined across creases
// by the summed votes of all the edges between them.
//
// Graph: every point joined to its k - 1 nearest neighbours (undirected). Hoppe's sign rule
// (flip n_j when n_i·n_j < 0) and weight 1 − |n_i·n_j| assume the normals turn smoothly; with
// crease-sharp normals (--method robust) a consistent pair across a 90° crease has n_i·n_j ≈ 0
// and across the 120° jump of a 60° wedge n_i·n_j < 0. So for pairs whose normals are more than
// 45° from parallel the agreement is measured on the mirrored normal (König & Gumhold,
// "Consistent propagation of normal orientations in point clouds", VMV 2009: [Konig09]): a =
// n_i·n_j', with n_j' = n_j mirrored in the plane that bisects the edge x_i x_j; for two faces of a
// crease sampled symmetrically about it a = +1 for a consistent pair, −1 otherwise. Pairs within
// 45° keep a = n_i·n_j: the mirror reads the edge direction, which position noise tilts (measured:
// the mirror everywhere turned half of the noisy CAD part inward). Signs are joined in two
// stages with a union-find whose links carry the sign relation that made them. First the sheets:
// the edges whose normals are within 20° of parallel, in row order (flip n_j when n_i·n_j < 0;
// within 20° that relation does not depend on which edge comes first, so no weights are sorted).
// Then the sheets join in rounds: the agreements of all the kNN edges between two sets (in the
// sets' frames) are summed, and pairs join strongest sum first, with its sign, when it is a
// clear majority (|Σa| >= 0.25 Σ|a| and >= 1); the next round sums again over the grown sets,
// until a round joins nothing. A single edge no longer decides a whole face: across a crease the
// mirrored agreement of one pair is ±1 whenever the normals are far apart, also when that is
// noise (a point near the crease carrying the other face's robust normal, noisy scan-line PCA
// normals, an edge mostly made of noise), and a minimum spanning tree takes the cheapest such
// edge as the only link between two faces (measured on 100k-point samples, before -> after:
// noisy scan-line cube, robust 81 -> 0.3 % of the normals inward, PCA 2.3 -> 1.0 %; a sphere with
// noise 0.3 % of its diameter, PCA 17 -> 1.3 %; the CAD part unchanged at <= 0.6 %). Evidence
// that contradicts itself, as at a T-junction (a sheet that runs on past the crease: ground under
// a wall, a floor slab touching a wall), keeps the sets apart until the majorities are done; they
// then join by the sign of their sum, strongest first, so that each connected component is
// oriented as one.
// Limitation: two sides of a part thinner than the kNN reach, with antiparallel normals, look
// like one consistently flipped sheet (none in the CAD sample: its thinnest place is the 60°
// wedge's tip, a crease).
//
// Outward sign, per connected component: the component's point of largest z (smallest index on
// ties) is made to point +z (its normal's z >= 0).
// For a closed surface that point is a top-most point, where the outward normal has z > 0, so the
// whole component ends up pointing outward. Open sheets seen from above (terrain, facades' tops)
// point up.
//
// Memory: the kNN rows (4 bytes per graph edge, 36 per point at k = 10) are found while the
// index is still held; the index is then released and the rows compacted in place to the kept
// edges (an edge whose reverse is in an earlier row is left out: about half of them), 4 bytes each
// plus a 4-byte row start per point, and the union-find 6 per point. Time: one kNN pass
// (parallel), one pass that compacts the rows (parallel, then a copy per block of rows) and a
// near-linear union-find. The joins of sheets add 28 bytes per edge between sheets and 5 per
// point: little where the sheets are large, most on normals that are mostly noise (a 1M-point
// sphere with noise 0.3 % of its diameter, half of its edges between sheets). With layered
// points (OrientRegionsOptions::layered), the sheet edges' adjacency lists add 8 bytes per point
// and 8 per sheet edge while the sheets grow.
// Against the earlier single spanning tree over weight-sorted edges, 1M points, 2 threads: orient
// phase 0.40 -> 0.30 s on a scan-line CAD part (peak 122 -> 127 MB), 0.17 -> 0.15 s on the city,
// 0.26 -> 0.13 s on a clean torus, 0.43 -> 1.00 s on the noisy sphere (peak 123 -> 226 MB).
// Deterministic for any thread count (the kNN rows are exact; everything after them is
// sequential).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "splatkit/shrinkable_array.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

inline constexpr std::size_t kOrientK = 10;  // kNN row length, the point itself included

struct OrientStats {
  std::size_t flipped = 0;     // output normals whose sign changed
  std::size_t components = 0;  // connected components of the kNN graph (isolated points count)
  std::size_t sheets = 0;      // smooth sheets before they were joined (step 1)
  // With evidence: the points whose sign the evidence decided (their set joined the evidence's
  // frame), and those among them left against their own non-zero vote.
  std::size_t by_evidence = 0;
  std::size_t against_evidence = 0;
  // The regional variant's last pass: points turned to follow their graph neighbours.
  std::size_t relabelled = 0;
  // Layered points whose normal became the mean of their oriented neighbours' (settle_layered).
  std::size_t settled = 0;
};

// The regional variant of the same joins (`estimate-normals --orient visibility`).
struct OrientRegionsOptions {
  // Keep apart, while the sheets grow (then within 11.5°, as with evidence), the points of an edge
  // that runs along both normals more than along the surface (|n·ê| > 1/2 at both ends: the two
  // sides of a wall or slab thinner than the kNN reach, or two facing surfaces across a narrow
  // gap), and measure such an edge's agreement on the mirrored normal, which says the two sides
  // face opposite ways.
  bool split_gaps = false;
  // #N or empty: an absolute vote per point in [-1, 1] for its current sign (positive: keep it),
  // e.g. visibility_votes.h. Each vote is an edge to a virtual point whose sign is fixed, summed
  // and joined like the edges between sheets, but in the majority rounds only when the sum is at
  // least 15 % of the set's points; a set joined to it takes its sign from the votes, others from
  // their top-most point. With votes the sheets grow only within 11.5° (not 20°), and a set the
  // majority rounds leave apart from the votes (an enclosed part that no view sees, such as the
  // rooms behind a building's walls) gets a prior that faces its own inside: the sum over its
  // points of n·(c − p)/|c − p|, c its centroid, as a vote of the whole set. Last, a point
  // whose signed agreements with its neighbours sum below −1/2 of their magnitudes turns.
  std::span<const float> evidence;
  // #N or empty: the points whose neighbourhood may hold two close faces (e.g. the normals that
  // widen_flat_normals.h took from a wider row). With split_gaps, a sheet edge at such a point
  // that runs oblique to its normals joins only when points joined to both its ends confirm it,
  // and where such a point's neighbourhood splits into two layers (layer_cuts.h) an edge to the
  // other layer is read as across the gap and one within its layer as along it, whatever the
  // edge's angle. The cuts take 4 bytes per point while the graph is built.
  // Once signed, such a point whose row showed no plane lies where faces meet (a crease, a thin
  // edge) or between the two faces of a slab, and its PCA normal is a blend that can lie more than
  // 90° from its own face's: it takes the mean of its graph neighbours' oriented normals (those
  // on its own layer) when they agree (the mean's length at least half their count) and its own
  // normal lies more than 18° from it.
  std::span<const uint8_t> layered;
  // Whether the layered points' normals are PCA blends: then their layers are cut and they settle
  // as above. Normals fitted to one face (`--method robust`) only confirm the sheet edges there:
  // settling them rounded the CAD part's creases (normals more than 30° off the reference 0.03 ->
  // 0.30 %, noisy part 1.2 -> 1.8 %), and the cuts turned parts of the real building's roof (roof
  // up 95.6 -> 77.8 %).
  bool blended_layers = true;
  // #N or empty: where finite, the cut (as layer_cuts.h gives it) between the two faces whose
  // model gave the point its normal (select_face_normals.h). With split_gaps, a sheet edge to a
  // point beyond it does not join: the points of both faces of a thin wall that took one wall
  // model carry the very same normal, so neither the 11.5° nor the gap test keeps them apart, and
  // on the noisy scan-line city whole scan lines joined the other face (walls out 99.25 % with
  // the rule, 97.92 % without). Only the sheets: read as layers in the rounds and the settling
  // too, the cuts turned whole slabs (93.5 % agree).
  std::span<const float> face_cuts;
};

// index: built over positions (#N); taken by value and released once the kNN graph is built, so a
// caller done with it moves it in and the forest's peak does not hold it. normals: #N unit
// normals, re-signed in place. k >= 2 and matching sizes, else std::invalid_argument.
OrientStats orient_normals_mst(SpatialIndex index, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k = kOrientK);

// Fills out (#N by k - 1, row-major) with each point's k - 1 nearest other points, ordered by
// (squared distance, index), as SpatialIndex::knn_all's columns 1..k-1.
using KnnRowsFn = std::function<void(std::size_t k, std::span<uint32_t> out)>;

// A KnnRowsFn's work over the whole cloud's index.
void index_knn_rows(const SpatialIndex& index, std::size_t k, std::span<uint32_t> out);

// The rows the orientation joins, #N by min(k, N) - 1, from `rows`: found ahead by a caller that
// reads them first (estimate_normals bounds the radii by the nearest of them). k >= 2.
ShrinkableArray orient_knn_rows(const KnnRowsFn& rows, std::size_t n, std::size_t k = kOrientK);

// The same with the kNN rows from `rows` instead of an index (a cloud processed in pieces,
// splat_pieces.h).
OrientStats orient_normals_mst(const KnnRowsFn& rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k = kOrientK);

// The same over rows from orient_knn_rows(…, positions.size(), k), which it takes (their memory
// becomes the graph's).
OrientStats orient_normals_mst(ShrinkableArray rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k = kOrientK,
                               const OrientRegionsOptions& regions = {});

}  // namespace splatkit
