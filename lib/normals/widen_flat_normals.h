// widen_flat_normals: a wider PCA row where the k-row's plane is ill-defined, for
// `estimate-normals --method pca`.
//
// PCA over the k nearest points fails where those points do not lie on one plane at the scale of
// the row: on the two faces of a wall or slab thinner than the row's reach (the row takes points
// of both, and its spread across the plane is then comparable to its spread along it, so the
// plane's normal may tilt anywhere). A wider row's in-plane spread grows with its size while the
// spread across does not. The sign of trouble is the ratio of the two smallest eigenvalues of
// the row's covariance, λ0 / λ1: near 0 the plane is well defined (whatever the noise), near 1
// any direction in the λ0-λ1 plane is as good a normal as another. Points whose k-row has
// λ0 / λ1 above kWidenRatio take the PCA normal of their 2k nearest points. A choice of the
// neighbourhood's size by what the neighbourhood shows, as Mitra, Nguyen and Guibas choose it by
// noise and curvature ([Mitra04] in docs/references.md); with a fixed second scale rather than
// their model's optimum.
// Measured on the scan test set (scripts/make-scan-set.sh: walls and slabs 0.3 m thick sampled on
// both faces at 0.19 m, scan lines, noise of 0.3 spacing), points more than 30° off the reference
// normal, k = 16 -> with the rule: slabs 34 -> 9 %, roofs 32 -> 2 %, walls 18 -> 12 % (the rest
// at openings and corners); the rule was also compared with choosing the row by the smaller
// surface variation (Pauly02; few slab points improve: the wider row takes more of the other
// face, so its variation does not fall) and with λ0 / λ1 of the two rows (worse on slabs).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "normals/neighborhood_pca.h"
#include "normals/select_face_normals.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

inline constexpr float kWidenRatio = 0.3f;

// λ0 / λ1 of a PCA (0 when λ1 is 0).
float flatness_ratio(const PcaNormal& pca);

// For each of `points` (indices into positions and normals), the PCA over its 2k nearest points
// (k >= 1) replaces normals[i] unless that row is degenerate. index: built over positions.
// models (empty, or as positions): each point's entry receives its 2k-row's face model
// (select_face_normals.h): two parallel faces where the row's offsets along the normal split into
// two parts kLayerSeparation pooled deviations apart that lie over each other (kLayerOverlap, as
// layer_cuts.h) and, about their own centroids, show a plane (λ0 / λ1 <= kWidenRatio: a crease or
// a wedge split so does not), refitted a few times to both parts at once, and normals[i] then
// becomes the faces' normal; else the 2k-row's plane.
// sq_reach (empty, or as positions): each point's entry is raised to the squared distance of its
// 2k-row's last point (+inf when the cloud has fewer points). Returns how many normals were
// replaced. Each point's result depends on its own row only: the same for any thread count.
std::size_t widen_flat_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                               std::span<const uint32_t> points, std::size_t k,
                               std::span<Vec3f> normals, std::span<float> sq_reach = {},
                               std::span<FaceModel> models = {});

}  // namespace splatkit
