// robust_normals: crease-preserving normals for `estimate-normals --method robust`: sharp edges
// and clip partners ([IvoMSc] §2, docs/references.md) need normals that respect the
// discontinuities instead of blending across them.
//
// Method: robust statistics with random sampling, after Li, Schnabel, Klein, Cheng, Dang, Jin,
// "Robust normal estimation for point clouds with sharp features" (Computers & Graphics 34, 2010;
// [Li10]). PCA fits one plane to a neighbourhood that straddles a crease and returns a blend of the
// two sides; Li et al. instead look for the plane that the point's OWN side supports best:
// candidate planes through random triplets of neighbours are scored by a kernel density of their
// residuals, with the kernel's bandwidth taken from a robust (order-statistic) scale estimate, and
// the winner must pass close to the query point. Inside a ball centred on a point near a crease,
// the point's own side always covers more of the ball than the other side, so its plane collects
// the most inliers and wins; the normal is then refit by PCA over that plane's inliers only. Here:
// 32 triplets per point, every other one through the point itself; pass 1 keeps the candidates that
// pass within their own band (2.5 σ, σ from their residuals' 1/3 quantile, so a corner whose own
// face holds a third of the ball still works) and takes the smallest σ as the common scale; pass 2
// scores the kept candidates by an Epanechnikov kernel of their residuals at bandwidth 2.5 σ; two
// PCA refits over the winner's inliers follow. A plane sets the scale, and the final one is
// accepted, only when its inliers spread over a patch rather than a line: on scan lines with range
// noise each line lies in the sensor's sweep plane, which otherwise wins at any angle to the
// surface (the point then keeps its PCA normal).
//
// Measured limits: points within ~1/3 spacing of a curved rim (hole, boss) can take the flat face's
// normal (8 of 200k on the CAD part); within a spacing of a crease and with noise of half a
// spacing, neither side can be told apart (see scripts/bench/normals-accuracy.sh).
//
// Why this one: it needs nothing but the kNN rows we already compute, is exact on noiseless planes
// at any distance from a crease ([Jones04] mollify towards a smooth field and still round creases
// off by about a kernel width), handles noise through the scale estimate, and its cost is per point
// and local, so it can be limited to the few points that need it ([Boulch12]'s randomized Hough
// transform gives similar quality, but accumulates hundreds of hypotheses per point and quantises
// the normal into bins).
//
// Speed: only points whose PCA neighbourhood is not planar get the robust treatment. The test is
// the surface variation λ0 / (λ0 + λ1 + λ2) of the PCA ([Pauly02]) against a threshold
// that adapts to the cloud: max(kMinVariation, kVariationFactor × the median over all points), so
// noise raises the bar with the typical planar value and only outliers of the distribution — the
// creases, corners and strongly curved parts — are refined. Within a fit, candidates that can
// change neither the scale nor the winner are skipped, and a candidate's order statistic is
// selected only when it beats the best so far (about 4 selections of 32): the same result as
// scoring every candidate in full, at under half the cost (README.md, Choices).
//
// Noise: with noisy points, PCA over k = 16 is itself too noisy on plain faces (at a noise of 0.5
// spacing, ~8° RMS). The median surface variation v of the k-neighbourhoods measures it: for a flat
// sample the RMS angle error of PCA over K points is about 2 sqrt(v k) / K. When that exceeds
// kTargetRmsRad at K = k, the cloud is "noisy": every point is refit over the K that meets the
// target (capped at max_k) — PCA for the planar ones, the robust fit for the others.
//
// Determinism: each point's random triplets come from DeterministicRng(seed, point index), and its
// result depends only on its own exact kNN row, so the output is identical for any thread count.
// Never NaN: a point whose robust fit fails (too few neighbours, all candidate triplets
// degenerate) keeps its PCA normal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

struct PcaNormal;

// Below kMinVariation PCA is already within ~1° (measured on the CAD part: a plane point whose
// 16-row holds a point or two of another face 2 spacings away has v ~ 4e-3), and smooth
// cylinders of radius >= ~10 spacings stay below it. 1e-4 sent 3x as many points (the cylinders)
// through the robust fit, which was slower and a little worse there (0.5° RMS against PCA's 0.1°).
inline constexpr double kMinVariation = 1e-3;
inline constexpr double kVariationFactor = 3.0;  // times the median surface variation
inline constexpr double kTargetRmsRad = 0.05;    // ~3°: the noise level that switches to larger K

struct RobustNormalOptions {
  std::size_t pca_k = 16;       // the k of the neighbourhoods the variations come from
  std::size_t k = 32;           // points in the robust neighbourhood, the point itself included
  std::size_t max_k = 64;       // cap of the neighbourhood of noisy clouds
  std::size_t candidates = 32;  // random triplets (candidate planes) per refined point
  uint64_t seed = 0x5eed5eed;
  // #N numbers of the points in the caller's cloud when it renumbered them (a permutation of
  // 0..N-1), so that results do not depend on the renumbering: they key each point's random
  // stream (with `seed`) and pick the sample of a noisy cloud's wide neighbourhoods. Empty: the
  // index in `positions`.
  std::span<const uint32_t> stream_ids;
};

struct RobustNormalStats {
  std::size_t candidates = 0;  // points above the variation threshold (noisy clouds decide again
                               // on each point's wide row)
  std::size_t refined = 0;     // points whose normal came from the robust fit
  double threshold = 0;        // the surface-variation threshold used
  double median_variation = 0;
  std::size_t k = 0;          // neighbourhood used (> options.k for a noisy cloud)
  bool noisy = false;         // every point refit over k neighbours
  double wide_threshold = 0;  // noisy: the variation of a k-row above which it gets the robust fit
};

// λ0 / (λ0 + λ1 + λ2) of a PCA (eigenvalues ascending): 0 on a plane, 1/3 for an isotropic
// neighbourhood; 0 for a zero matrix.
double surface_variation(const PcaNormal& pca);

// index: built over positions (#N). variation: #N surface variations from the PCA pass (values
// < 0 mark points to skip, e.g. degenerate ones whose normal came from a wider neighbourhood).
// normals: #N unit PCA normals in, refined normals out, unoriented with neighborhood_pca's
// canonical sign (a clean cloud changes only the refined points; a noisy one every point that
// is not skipped). Runs in parallel with TBB.
RobustNormalStats robust_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                                 std::span<const float> variation, std::span<Vec3f> normals,
                                 const RobustNormalOptions& options = {});

}  // namespace splatkit
