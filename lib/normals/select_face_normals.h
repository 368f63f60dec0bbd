// select_face_normals: each point where thin parts meet takes the face model, among its
// neighbours', that passes through it and explains most of its wider row, for
// `estimate-normals --method pca`.
//
// On a wall or slab thinner than the kNN reach, sampled on both faces, a k-row holds both faces;
// where such a wall meets a floor slab, a balcony or the ground it also holds the perpendicular
// part, and its PCA plane blends them: on the scan test set's noisy scan-line city
// (scripts/make-scan-set.sh) 5 571 wall normals lay more than 60° off the wall, 3 233 slab
// normals off the slab, and a blend that far from its own face can come out on the wrong side
// after any orientation. Neither a wider row nor a robust fit through random triplets escapes it
// there (the other face and the junction lie as near as the next scan line).
//
// Each point's "face model" is what its row shows: a plane (normal, offset of the row's centroid
// along it), or, for a point whose k-row showed no plane and whose 2k-row splits into two layers
// (widen_flat_normals.h: 5 pooled deviations apart, lying over each other, a plane about their
// own centroids), two parallel faces fitted to both layers together. A point where rows blend
// (λ0 / λ1 of its k-row above kSelectRatio) then looks at the models of its k nearest points
// (itself included), as Li et al. look at candidate planes ([Li10] in docs/references.md), but
// with the neighbours' own fits as the candidates: a model counts when the point lies within the
// band of one of its faces, and the one with the most points of the point's 2k-row within the
// band of its faces wins (ties: the nearer neighbour). A wall point beside a slab sees the slab's
// top face pass below it, out of the band, and a wall model hold both faces of the wall. The band
// is kFaceBand times the median residual deviation of the widened rows' fits (face_noise): the
// spread of the thin parts' rows about their models, noise and the misfit of the rows that did not
// split (0.13 m on the noisy scan-line city, whose noise is 0.056 m).
//
// Measured on the scan test set (scripts/make-scan-set.sh), normals more than 60° off the
// reference's line before orientation, before -> after: city-scan-noisy walls 5 571 -> 2 518,
// slabs 3 233 -> 1 751 (mean angle 17.5 -> 9.0° and 13.0 -> 8.9°); city-noisy walls 3 666 -> 2 675,
// slabs 2 219 -> 1 507. The band is a narrow choice: 0.75× of it turned 23 points of the noisy
// CAD part's 60° wedge tip (a thin part whose faces are not parallel: a face's model passes
// through the other face's points there and holds more of the row), 1.4× of it left 1 376 of the
// noisy scan-line city's walls facing in (709 at 1×).
//
// A cloud without thin parts (thin_parts) is left as it is. Deterministic: each
// point's result depends on its own row and the models, which depend on rows only; the same for
// any thread count.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

inline constexpr float kSelectRatio = 0.1f;
inline constexpr float kFaceBand = 2.0f;

// A point's face model, its normal being the point's normal: the offsets along it, from the point,
// of the faces' centroids (a == b: one plane), and the fit's residual variance along the normal
// per point (NaN: no model, e.g. a degenerate row).
struct FaceModel {
  float a = 0, b = 0;
  float variance = std::numeric_limits<float>::quiet_NaN();
};

// Whether the cloud has thin parts sampled on both faces, for which the choice is made: at least
// a quarter of the widened rows (`widened`) were fitted as two faces (`two_face`). Measured share:
// the scan set's cities 40-85 %, the CAD parts and the facade at most 1 %, the real building 17 %,
// splat-synth's city with one-sided walls 20 % (there the choice among crease planes turned 6 %
// of its normals: e2e.normals).
inline constexpr std::size_t kThinShareInverse = 4;  // a quarter
inline bool thin_parts(std::size_t two_face, std::size_t widened) {
  return widened > 0 && two_face * kThinShareInverse >= widened;
}

// The median residual deviation of the models of `points` (0 when none has one): with the widened
// points, the spread that sets the band.
float face_noise(std::span<const FaceModel> models, std::span<const uint32_t> points);

// For each of `points` (indices into positions), the normal of the winning model among its k
// nearest points' (normals and models: #N), judged over its 2k nearest points with the band
// kFaceBand × noise; written to out (#N; the others untouched). index: built over positions.
// sq_reach (empty, or #N): each point's entry is raised to the squared distance of its 2k-row's
// last point (+inf when the cloud has fewer points). cuts (empty, or #N): where the winner has two
// faces, the offset along the chosen normal, from the point, half-way between them (as
// layer_cuts.h gives it: the orientation reads its neighbours beyond it as the other face), NaN
// elsewhere. Returns how many points took a normal other than their own.
std::size_t select_face_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                                std::span<const uint32_t> points, std::size_t k,
                                std::span<const Vec3f> normals, std::span<const FaceModel> models,
                                float noise, std::span<Vec3f> out, std::span<float> sq_reach = {},
                                std::span<float> cuts = {});

}  // namespace splatkit
