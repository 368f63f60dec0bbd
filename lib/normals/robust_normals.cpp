#include "normals/robust_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <vector>

#include "normals/fit_plane.h"
#include "normals/neighborhood_pca.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/pca_normal.h"

namespace splatkit {

namespace {

// The residual quantile that sets the scale: a third of the neighbourhood, so a point near a
// corner, whose own face holds only about a third of its neighbours, still finds that face.
constexpr double kScaleQuantile = 1.0 / 3.0;
// Φ⁻¹((1 + q) / 2) for q = 1/3: turns that order statistic of |residual| into a Gaussian σ.
constexpr double kScaleToSigma = 1.0 / 0.4307;
constexpr double kInlierSigmas = 2.5;  // kernel bandwidth and inlier band, in σ
// Floor of the bandwidth relative to the neighbourhood radius: on exact planes σ is ~0 and the
// band must still absorb float rounding of the coordinates.
constexpr double kMinBandwidth = 1e-4;
// Triplets whose sine of the smallest angle is below this give unstable planes: skipped.
constexpr float kMinTripletSine2 = 0.01f;
constexpr int kRefits = 2;
// A plane must rest on a two-dimensional patch of its neighbours: the in-plane spread of its
// inliers, smaller over larger (the PCA's middle eigenvalue over its largest), at least this. A
// scan line with range noise lies in the plane of the sensor's sweep, so a candidate through it
// collects the line alone with tiny residuals and would otherwise set the scale and win, at any
// angle to the surface. On splat-synth's CAD part (100k points, scan-line sampling with noise),
// normals off by more than 60°: 5 762 -> 1 441 (PCA: 123), the wrong winners' inliers had a median
// spread of 0.08 against 0.90 for the right ones; scan lines without noise 342 -> 145; the
// stratified sample unchanged (0.2 cost it 10 crease points; a half disc, a point on a crease, is
// 0.28).
constexpr double kMinInlierSpread = 0.15;
// Noisy clouds: a wide row is planar while its variation is below this factor times the median
// variation of wide rows, estimated on every kWideSampleStep-th point.
constexpr double kNoisyFactor = 2.0;
constexpr std::size_t kWideSampleStep = 64;

// Per-thread scratch for one point's fit.
struct Scratch {
  std::vector<Vec3f> local;  // neighbours relative to the query point
  // The same coordinates as separate arrays, so the residual loops vectorise.
  std::vector<float> x, y, z;
  std::vector<float> residuals;
  std::vector<Plane> planes;
};

// The rank-th smallest |residual| (rank >= 1) of the neighbours to `plane`, residuals computed
// as dot(n, q) - offset is, when it is below `bound`; otherwise `bound`. Only the residuals below
// the bound take part in the selection: usually a few more than `rank`.
float order_statistic_below(const Plane& plane, std::size_t rank, float bound, Scratch& s) {
  const std::size_t m = s.x.size();
  const float nx = plane.n.x, ny = plane.n.y, nz = plane.n.z, offset = plane.offset;
  const float *x = s.x.data(), *y = s.y.data(), *z = s.z.data();
  float* r = s.residuals.data();
  for (std::size_t j = 0; j < m; ++j) r[j] = std::fabs(nx * x[j] + ny * y[j] + nz * z[j] - offset);
  std::size_t below = 0;
  for (std::size_t j = 0; j < m; ++j) {
    r[below] = r[j];
    below += r[j] < bound ? 1 : 0;
  }
  if (below < rank) return bound;
  std::nth_element(r, r + (rank - 1), r + below);
  return r[rank - 1];
}

// Σ max(0, 1 - r² / h²) over the neighbours' residuals r to `plane` (Epanechnikov kernel),
// summed in neighbour order.
float kernel_score(const Plane& plane, float inv_h2, Scratch& s) {
  const std::size_t m = s.x.size();
  const float nx = plane.n.x, ny = plane.n.y, nz = plane.n.z, offset = plane.offset;
  const float *x = s.x.data(), *y = s.y.data(), *z = s.z.data();
  float* w = s.residuals.data();
  for (std::size_t j = 0; j < m; ++j) {
    const float r = nx * x[j] + ny * y[j] + nz * z[j] - offset;
    w[j] = std::max(0.0f, 1.0f - r * r * inv_h2);
  }
  float score = 0;
  for (std::size_t j = 0; j < m; ++j) score += w[j];
  return score;
}

// Candidate planes through random triplets of the neighbourhood; every other one passes through
// the query point itself (local[0] = origin), which raises the odds of a triplet lying wholly on
// the point's own side when that side holds only a third of the ball.
void sample_planes(std::span<const Vec3f> local, std::size_t count, DeterministicRng& rng,
                   std::vector<Plane>& planes) {
  planes.clear();
  const uint64_t m = local.size();
  for (std::size_t attempt = 0; attempt < 4 * count && planes.size() < count; ++attempt) {
    const uint64_t a = (attempt % 2 == 0) ? 0 : rng.next() % m;
    const uint64_t b = rng.next() % m, c = rng.next() % m;
    if (a == b || a == c || b == c) continue;
    Plane p;
    if (triplet_plane(local[a], local[b], local[c], kMinTripletSine2, p)) planes.push_back(p);
  }
}

// The robust normal of one point from its neighbourhood (local[0] is the point, at the origin);
// false when no fit is found.
bool robust_fit(std::span<const Vec3f> local, std::size_t candidates, DeterministicRng& rng,
                Scratch& s, Vec3f& normal) {
  const std::size_t m = local.size();
  sample_planes(local, candidates, rng, s.planes);
  if (s.planes.empty()) return false;
  float radius2 = 0;
  for (const Vec3f& q : local) radius2 = std::max(radius2, squared_norm(q));
  const float floor_band = static_cast<float>(kMinBandwidth) * std::sqrt(radius2);

  // Pass 1: the robust scale, the smallest residual order statistic over the candidates that pass
  // within their own band of the query point (least k-th order statistic) and whose inliers in
  // that band span a patch (inliers_span_plane, fit_plane.h). Candidates that do not pass within
  // their band are dropped: a plane of the other side, exact and so with a tiny band of its own,
  // must not win pass 2 just because a curved own side widens the common bandwidth. Pruned exactly:
  // with h = the band of the best statistic so far, a candidate farther than h from the query point
  // can neither lower the statistic (its own band would be narrower) nor pass pass 2 (whose
  // bandwidth only shrinks); one within h is kept, and its statistic matters only when at least
  // `rank` residuals are below the best so far — then it is selected exactly.
  const std::size_t rank = std::max<std::size_t>(3, static_cast<std::size_t>(kScaleQuantile * m));
  const auto band_per_stat = static_cast<float>(kInlierSigmas * kScaleToSigma);
  float best_stat = INFINITY, h = INFINITY;
  s.x.resize(m), s.y.resize(m), s.z.resize(m), s.residuals.resize(m);
  for (std::size_t j = 0; j < m; ++j) s.x[j] = local[j].x, s.y[j] = local[j].y, s.z[j] = local[j].z;
  std::size_t kept = 0;
  for (const Plane& p : s.planes) {
    if (!(std::fabs(p.offset) <= h)) continue;
    const float stat = order_statistic_below(p, rank, best_stat, s);
    if (stat < best_stat) {
      const float band = std::max(floor_band, band_per_stat * stat);
      if (!(std::fabs(p.offset) <= band)) continue;
      if (inliers_span_plane(local, p, band, kMinInlierSpread)) {
        best_stat = stat;
        h = band;
      }
    }
    s.planes[kept++] = p;
  }
  s.planes.resize(kept);
  // No candidate rests on a patch: no scale to judge by (the point keeps its PCA normal).
  if (kept == 0 || best_stat == INFINITY) return false;

  // Pass 2: kernel density of the residuals at bandwidth h (Epanechnikov), among the planes that
  // pass within h of the query point; the first best wins ties.
  const float inv_h2 = 1.0f / (h * h);
  float best_score = -1;
  const Plane* best = nullptr;
  for (const Plane& p : s.planes) {
    if (!(std::fabs(p.offset) <= h)) continue;
    const float score = kernel_score(p, inv_h2, s);
    if (score > best_score) best_score = score, best = &p;
  }
  if (!best) return false;

  // Refit by PCA over the inliers, twice: the second pass uses the refit plane's own inliers.
  Plane plane = *best;
  for (int pass = 0; pass < kRefits; ++pass) {
    Plane next;
    if (!refit_plane(local, plane, h, next)) break;
    plane = next;
  }
  if (!(std::fabs(plane.offset) <= 2 * h) || !inliers_span_plane(local, plane, h, kMinInlierSpread))
    return false;
  normal = canonical_sign(plane.n);
  return true;
}

// The median of the valid (>= 0) variations; 0 when there are none.
double median_variation(std::span<const float> variation) {
  std::vector<float> valid;
  valid.reserve(variation.size());
  for (float v : variation)
    if (v >= 0) valid.push_back(v);
  if (valid.empty()) return 0;
  const auto mid = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2);
  std::nth_element(valid.begin(), mid, valid.end());
  return *mid;
}

// The robust normal of point i from its kNN row (ids[0] is i or a duplicate of it).
bool fit_point(std::span<const Vec3f> positions, uint32_t i, std::span<const uint32_t> ids,
               const RobustNormalOptions& options, Scratch& s, Vec3f& normal) {
  const Vec3f p = positions[i];
  s.local.clear();
  for (const uint32_t j : ids)
    if (j != SpatialIndex::kNone) s.local.push_back(positions[j] - p);
  if (s.local.size() < 6) return false;
  s.local[0] = Vec3f{0, 0, 0};
  DeterministicRng rng(options.seed, options.stream_ids.empty() ? i : options.stream_ids[i]);
  return robust_fit(s.local, options.candidates, rng, s, normal);
}

// Clean cloud: only the listed points, each with its own kNN query.
std::size_t refine_points(const SpatialIndex& index, std::span<const Vec3f> positions,
                          std::span<const uint32_t> points, std::size_t k, std::span<Vec3f> normals,
                          const RobustNormalOptions& options) {
  std::atomic<std::size_t> refined{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Scratch s;
                      std::vector<uint32_t> ids(k);
                      std::size_t done = 0;
                      for (std::size_t r = range.begin(); r != range.end(); ++r) {
                        const uint32_t i = points[r];
                        const std::size_t m = index.knn(positions[i], k, ids.data(), nullptr);
                        Vec3f n;
                        if (fit_point(positions, i, std::span(ids).first(m), options, s, n)) {
                          normals[i] = n;
                          ++done;
                        }
                      }
                      refined += done;
                    });
  return refined;
}

// The median surface variation of k-rows over every kWideSampleStep-th point (by `ids`, the
// points' numbers in the caller's cloud, when given). Measured, not
// scaled from the narrow rows' median: once the noise is as large as the neighbourhood's extent
// the variation no longer falls as 1/k (at 1M points and noise 1.6 spacings, scaling sent 71 %
// of the points through the robust fit).
double wide_median_variation(const SpatialIndex& index, std::span<const Vec3f> positions,
                             std::span<const float> variation, std::size_t k,
                             std::span<const uint32_t> numbers) {
  const std::size_t n = positions.size();
  const std::size_t samples = (n + kWideSampleStep - 1) / kWideSampleStep;
  std::vector<uint32_t> at;  // sample r -> the point numbered r * kWideSampleStep
  if (!numbers.empty()) {
    at.resize(samples);
    for (std::size_t t = 0; t < n; ++t)
      if (numbers[t] % kWideSampleStep == 0)
        at[numbers[t] / kWideSampleStep] = static_cast<uint32_t>(t);
  }
  std::vector<float> wide(samples, -1.0f);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples, 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<uint32_t> ids(k);
                      for (std::size_t r = range.begin(); r != range.end(); ++r) {
                        const std::size_t i = at.empty() ? r * kWideSampleStep : at[r];
                        if (variation[i] < 0) continue;
                        const std::size_t m = index.knn(positions[i], k, ids.data(), nullptr);
                        wide[r] = static_cast<float>(surface_variation(
                            neighborhood_pca(positions, std::span(ids).first(m))));
                      }
                    });
  return median_variation(wide);
}

// Noisy cloud: every point over k neighbours, streamed. The PCA of the wider row decides: planar
// (its variation below `threshold`) keeps it, anything else gets the robust fit.
std::size_t refine_all(const SpatialIndex& index, std::span<const Vec3f> positions,
                       std::span<const float> variation, float threshold, std::size_t k,
                       std::span<Vec3f> normals, const RobustNormalOptions& options) {
  std::atomic<std::size_t> refined{0};
  index.for_each_knn_block(k, [&](std::span<const uint32_t> queries,
                                  std::span<const uint32_t> indices, std::span<const float>) {
    Scratch s;
    std::size_t done = 0;
    for (std::size_t r = 0; r < queries.size(); ++r) {
      const uint32_t i = queries[r];
      if (variation[i] < 0) continue;
      const std::span<const uint32_t> row = indices.subspan(r * k, k);
      const PcaNormal pca = neighborhood_pca(positions, row);
      Vec3f n;
      if (surface_variation(pca) > threshold) {
        if (fit_point(positions, i, row, options, s, n)) normals[i] = n, ++done;
      } else if (!pca.degenerate) {
        normals[i] = pca.normal;
      }
    }
    refined += done;
  });
  return refined;
}

}  // namespace

double surface_variation(const PcaNormal& pca) {
  const double sum = pca.eigenvalues[0] + pca.eigenvalues[1] + pca.eigenvalues[2];
  return sum > 0 ? pca.eigenvalues[0] / sum : 0.0;
}

RobustNormalStats robust_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                                 std::span<const float> variation, std::span<Vec3f> normals,
                                 const RobustNormalOptions& options) {
  RobustNormalStats stats;
  stats.median_variation = median_variation(variation);
  stats.threshold = std::max(kMinVariation, kVariationFactor * stats.median_variation);
  const auto threshold = static_cast<float>(stats.threshold);
  std::vector<uint32_t> points;
  for (std::size_t i = 0; i < variation.size(); ++i)
    if (variation[i] > threshold) points.push_back(static_cast<uint32_t>(i));
  stats.candidates = points.size();

  // K meeting the target RMS error on flat parts: 2 sqrt(v k) / K <= kTargetRmsRad.
  const double pca_k = static_cast<double>(std::max<std::size_t>(options.pca_k, 3));
  const double needed = 2 * std::sqrt(stats.median_variation * pca_k) / kTargetRmsRad;
  stats.noisy = needed > pca_k;
  stats.k = stats.noisy ? std::clamp(static_cast<std::size_t>(std::ceil(needed)), options.k,
                                     std::max(options.k, options.max_k))
                        : options.k;
  stats.k = std::min(stats.k, index.size());
  if (stats.k < 6 || options.candidates == 0) return stats;
  if (stats.noisy)
    stats.wide_threshold = kNoisyFactor * wide_median_variation(index, positions, variation,
                                                                stats.k, options.stream_ids);
  const auto wide_threshold = static_cast<float>(stats.wide_threshold);
  stats.refined = stats.noisy ? refine_all(index, positions, variation, wide_threshold, stats.k,
                                           normals, options)
                              : refine_points(index, positions, points, stats.k, normals, options);
  return stats;
}

}  // namespace splatkit
