#include "normals/pca_normals_and_radii.h"

#include <algorithm>
#include <atomic>
#include <mutex>

#include "normals/cover_splat.h"
#include "normals/neighborhood_pca.h"
#include "normals/robust_normals.h"
#include "normals/splat_radius.h"
#include "normals/widen_flat_normals.h"

namespace splatkit {

namespace {

constexpr std::size_t kPrefetchRows = 4;

// The row's plane as a one-face model: the centroid's offset along the normal from the point,
// and the residual variance along it.
FaceModel plane_model(std::span<const Vec3f> positions, uint32_t i,
                      std::span<const uint32_t> row, const PcaNormal& pca) {
  double sum = 0;
  std::size_t count = 0;
  for (uint32_t j : row) {
    if (j == SpatialIndex::kNone) continue;
    sum += dot(pca.normal, positions[j] - positions[i]);
    ++count;
  }
  FaceModel m;
  if (count == 0) return m;
  m.a = m.b = static_cast<float>(sum / static_cast<double>(count));
  m.variance = static_cast<float>(pca.eigenvalues[0] / static_cast<double>(count));
  return m;
}

// Calls `progress` from whichever worker gets the lock; the others skip (the tools' callbacks are
// not thread-safe, and a skipped update is harmless).
class SharedProgress {
 public:
  SharedProgress(const ProgressFn& fn, double from, double to, std::size_t total, const char* phase)
      : fn_(fn), from_(from), to_(to), total_(std::max<std::size_t>(total, 1)), phase_(phase) {}
  void add(std::size_t done) {
    const std::size_t now = done_.fetch_add(done) + done;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (lock.owns_lock())
      fn_(from_ + (to_ - from_) * static_cast<double>(now) / static_cast<double>(total_), phase_);
  }

 private:
  const ProgressFn& fn_;
  double from_, to_;
  std::size_t total_;
  const char* phase_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
};

}  // namespace

// The splat of point i from its kNN row (positions' indices, the point first; squared distances),
// by the options' rule, written to the cloud's radii (and axes, minor radii). Returns whether the
// row left the point's cover cell open (cover_splat.h): a wider row may close it.
bool fit_splat(SplatCloud& cloud, const NormalOptions& o, uint32_t i, std::span<const uint32_t> row,
               std::span<const float> sq_dists, std::span<const Vec3f> final_normals) {
  // The whole row, as the mean-kNN rule always read it: duplicates (distance 0) are skipped.
  const float mean_knn = splat_radius(sq_dists, o.radius_k);
  if (o.radius_rule == RadiusRule::kMeanKnn) {
    cloud.radii[i] = mean_knn;
    return false;
  }
  // Only duplicates in the row: phase 3 leaves 0 (an isolated point, filled later); a refit keeps
  // the radius resolve_degenerate_normals took from a wider row.
  if (mean_knn == 0) return false;
  const SplatShape s = cover_splat(cloud.positions[i], cloud.normals[i], cloud.positions, row,
                                   kCoverCapScale * mean_knn, o.ellipses, final_normals);
  cloud.radii[i] = s.radius;
  if (o.ellipses) {
    cloud.axes[i] = s.axis;
    cloud.minor_radii[i] = s.minor_radius;
  }
  return s.open;
}

void pca_normals_and_radii(const SpatialIndex& index, SplatCloud& cloud, const NormalOptions& o,
                           std::vector<uint8_t>& flags, std::vector<float>& variation,
                           std::span<float> sq_reach, const ProgressFn& progress,
                           std::span<uint32_t> head_rows, std::span<float> eigen_ratio,
                           std::span<FaceModel> models) {
  const std::size_t row_k = row_size(o);
  const std::size_t head = cloud.size() ? head_rows.size() / cloud.size() : 0;
  const std::span<const Vec3f> positions(cloud.positions);
  SharedProgress shared(progress, 0.15, 0.6, cloud.size(), "normals");
  index.for_each_knn_block(
      row_k, [&](std::span<const uint32_t> queries, std::span<const uint32_t> indices,
                 std::span<const float> sq_dists) {
        for (std::size_t r = 0; r < queries.size(); ++r) {
          // The rows' points are scattered over the cloud: fetch a few rows ahead.
          if (r + kPrefetchRows < queries.size()) {
            for (uint32_t j : indices.subspan((r + kPrefetchRows) * row_k, o.k))
              if (j != SpatialIndex::kNone) __builtin_prefetch(&positions[j]);
          }
          const uint32_t i = queries[r];
          const std::span<const uint32_t> nearest = indices.subspan(r * row_k, o.k);
          const PcaNormal pca = neighborhood_pca(positions, nearest);
          cloud.normals[i] = pca.normal;
          const bool thin = is_thread(pca, positions, i, nearest);
          uint8_t f = thin ? kDegenerateFlag : 0;
          if (!variation.empty())
            variation[i] = pca.degenerate ? -1.0f : static_cast<float>(surface_variation(pca));
          if (!eigen_ratio.empty()) eigen_ratio[i] = pca.degenerate ? -1.0f : flatness_ratio(pca);
          if (!models.empty() && !thin) models[i] = plane_model(positions, i, nearest, pca);
          if (fit_splat(cloud, o, i, indices.subspan(r * row_k, row_k),
                        sq_dists.subspan(r * row_k, row_k)))
            f |= kOpenCellFlag;
          flags[i] = f;
          if (!sq_reach.empty()) sq_reach[i] = sq_dists[r * row_k + row_k - 1];
          std::copy_n(indices.data() + r * row_k + 1, head, head_rows.data() + i * head);
        }
        shared.add(queries.size());
      });
}

}  // namespace splatkit
