// pca_normals_and_radii: phase 3 of estimate_normals (estimate_normals.h), one streamed kNN pass
// that gives every point its PCA normal and its splat, and fit_splat, the splat of one point from
// its kNN row by the options' rule, which the refit phase (refit_splats.h) uses too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "normals/estimate_normals.h"
#include "normals/select_face_normals.h"
#include "splatkit/spatial_index.h"

namespace splatkit {

// Flags of phase 3 per point.
// PCA neighbourhood degenerate or a thread (is_thread in neighborhood_pca.h): widened.
inline constexpr uint8_t kDegenerateFlag = 1;
inline constexpr uint8_t kOpenCellFlag = 2;    // cover cell left open by the row: refitted
// Rows of refitted splats are this many times the phase-3 row.
inline constexpr std::size_t kWideRowFactor = 4;

// Points per phase-3 kNN row, the point itself included.
inline std::size_t row_size(const NormalOptions& o) { return std::max(o.k, o.radius_k + 1); }

// The splat of point i from its kNN row (positions' indices, the point first; squared distances),
// by the options' rule, written to the cloud's radii (and axes, minor radii). final_normals: empty,
// or the normals the cover rule tells sheets apart by. Returns whether the row left the point's
// cover cell open (cover_splat.h): a wider row may close it.
bool fit_splat(SplatCloud& cloud, const NormalOptions& o, uint32_t i, std::span<const uint32_t> row,
               std::span<const float> sq_dists, std::span<const Vec3f> final_normals = {});

// Phase 3 over every point of the index (built over cloud.positions, #N): cloud.normals and
// cloud.radii (and axes, minor radii) set from each point's row of row_size(o) nearest points;
// flags (#N) marks the points whose neighbourhood is degenerate or thin (phase 4 widens it) and
// those whose cover cell the row left open (refitted from a wider row). variation (empty, or #N)
// receives the surface variation the robust method selects its points by (-1: degenerate, skip).
// sq_reach (empty, or #N) receives the squared distance of each row's last entry (+inf when the
// cloud has fewer points than a row). head_rows (empty, or #N by w, w < row_size(o)) receives each
// row's first w entries after the point itself: its w nearest other points, as a kNN query of
// w + 1 points gives them. eigen_ratio (empty, or #N) receives λ0 / λ1 of each row's PCA
// (widen_flat_normals.h; -1: degenerate). models (empty, or #N) receives each row's plane as a
// face model (select_face_normals.h; none for a degenerate row). Progress runs from 0.15 to 0.6.
void pca_normals_and_radii(const SpatialIndex& index, SplatCloud& cloud, const NormalOptions& o,
                           std::vector<uint8_t>& flags, std::vector<float>& variation,
                           std::span<float> sq_reach, const ProgressFn& progress,
                           std::span<uint32_t> head_rows = {},
                           std::span<float> eigen_ratio = {},
                           std::span<FaceModel> models = {});

}  // namespace splatkit
