// SplatPieces: estimate_normals' neighbourhood phases (estimate_normals.h: phase 3's PCA normals
// and splats, the degenerate neighbourhoods, the refits, the neighbours' median radii of the
// radius bound, and the kNN rows of the MST orientation) computed piece by piece, each piece with
// a halo of the points around it, with the very results of the whole-cloud run: the ground for
// clouds larger than memory.
//
// Pieces are runs of consecutive points of the cloud's Morton order (morton_order.h), of about
// piece_points points each, cut into cells: runs that share an octree cell, split until each
// holds at most 1/64 of the piece. A piece is processed with the points that lie within its
// cells' halo widths of the cells' bounding boxes, numbered in the same order as in the whole
// cloud, so kNN ties are broken alike. A query's answer there equals the whole cloud's when the
// ball from the point to its farthest answer lies inside its cell's region, that is when the
// ball's radius is at most the cell's halo: a subset's k-th distance is never shorter than the
// whole set's, so the ball drawn from the subset's answer contains the true one. Each phase
// checks this for every query of the piece's own points and, when a ball is wider, runs the
// piece again with that cell's halo widened. An outlier or a sparse corner so widens only its own
// cell's region (around a lone point, a ball), though a point far from everything still reaches
// much of the cloud. Each phase reads only the earlier phases' results of the halo's points,
// which the pieces that own them computed. Ties go alike only when the positions are numbered in
// Morton order: the caller renumbers them first.
//
// Memory: one piece with its halo at a time (its kd-tree, its rows, a copy of its points and
// their per-point values) besides the whole cloud's arrays, which the caller holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "normals/estimate_normals.h"
#include "normals/resolve_degenerate_normals.h"
#include "normals/select_face_normals.h"
#include "splatkit/vec3.h"

namespace splatkit {

class SplatPieces {
 public:
  struct Stats {
    std::size_t pieces = 0;
    std::size_t halo_points = 0;  // points loaded besides the pieces' own, summed over every load
    std::size_t reruns = 0;       // pieces run again with a wider halo
  };

  // positions: the whole cloud (#N), in Morton order; kept by reference. piece_points >= 1.
  SplatPieces(std::span<const Vec3f> positions, std::size_t piece_points);

  std::size_t pieces() const { return ranges_.size() - 1; }
  const Stats& stats() const { return stats_; }

  // Phase 3, the degenerate neighbourhoods, the wider rows and the refit phase of
  // estimate_normals for the whole cloud: cloud.normals, radii (and axes, minor radii with
  // o.ellipses) #N, set as the whole-cloud run sets them before isolated points are filled.
  // cloud.positions must be the span given to the constructor. Counts the degenerate, unresolved and refitted points into report.
  // Method pca only, without fit_centres (the caller checks).
  // head_rows (empty, or #N by w, w < row_size(o)): each point's w nearest other points, taken
  // from the rows the normals are computed from (pca_normals_and_radii), in whole-cloud numbers.
  // bridges receives the edges off the scan line of the degenerate points
  // (resolve_degenerate_normals.h), in whole-cloud numbers and in the whole-cloud run's order.
  // widened (#N) marks the points whose k-row showed no plane, which tried a wider row
  // (widen_flat_normals.h). face_cuts: as the whole-cloud run's (select_face_normals.h: #N, or
  // left empty when no point was widened).
  void normals_and_splats(SplatCloud& cloud, const NormalOptions& o, NormalReport& report,
                          const ProgressFn& progress, std::span<uint32_t> head_rows,
                          std::vector<Bridge>& bridges, std::span<uint8_t> widened,
                          std::vector<float>& face_cuts);

  // neighbour_median_radii (bound_radii.h) of the whole cloud, piece by piece.
  std::vector<float> neighbour_median_radii(const std::vector<float>& radii, std::size_t k);

  // Every point's k - 1 nearest other points (out: #N by k - 1), as orient_normals_mst's KnnRowsFn.
  void knn_rows(std::size_t k, std::span<uint32_t> out);

 private:
  struct Cell {
    std::size_t begin = 0, end = 0;  // points [begin, end)
    double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};  // their bounding box
  };
  struct Local;
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  Local load(std::size_t piece) const;
  // normals_and_splats' choice among the neighbours' face models, after the first pass over every
  // piece; marks the points whose normal changed for the refit (kOpenCellFlag).
  void select_faces(SplatCloud& cloud, const NormalOptions& o, NormalReport& report,
                    std::vector<uint8_t>& flags, const std::vector<FaceModel>& models,
                    const std::vector<float>& ratios, std::span<const uint8_t> widened,
                    std::vector<float>& face_cuts);
  template <class Attempt>
  Local run(std::size_t piece, Attempt&& attempt);

  std::span<const Vec3f> positions_;
  std::vector<std::size_t> ranges_;       // piece p: points [ranges_[p], ranges_[p + 1])
  std::vector<Cell> cells_;               // the pieces' cells, in order
  std::vector<std::size_t> piece_cells_;  // piece p: cells [piece_cells_[p], piece_cells_[p + 1])
  std::vector<double> halo_;              // per cell: the halo width that served its last phase
  Stats stats_;
};

}  // namespace splatkit
