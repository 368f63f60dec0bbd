#include "normals/remove_outliers.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "normals/neighborhood_pca.h"
#include "splatkit/spatial_index.h"

namespace splatkit {

namespace {

// Mean distance from each point to its k nearest other points (float, as PCL keeps it).
std::vector<float> mean_knn_distances(const SpatialIndex& index, std::size_t k) {
  std::vector<float> d(index.size(), 0.0f);
  index.for_each_knn_block(k + 1, [&](std::span<const uint32_t> queries,
                                      std::span<const uint32_t>, std::span<const float> sq) {
    for (std::size_t r = 0; r < queries.size(); ++r) {
      double sum = 0;
      for (std::size_t j = 1; j <= k; ++j) sum += std::sqrt(sq[r * (k + 1) + j]);
      d[queries[r]] = static_cast<float>(sum / static_cast<double>(k));
    }
  });
  return d;
}

// The plane rule: for each point, the PCA plane of its k nearest other points; the point's
// distance h to it against the plane's own RMS residual and the mean neighbour distance.
std::vector<uint8_t> off_plane(std::span<const Vec3f> positions, const SpatialIndex& index,
                               const OutlierOptions& o) {
  std::vector<uint8_t> out(positions.size(), 0);
  const std::size_t k = o.k;
  index.for_each_knn_block(k + 1, [&](std::span<const uint32_t> queries,
                                      std::span<const uint32_t> rows, std::span<const float> sq) {
    for (std::size_t r = 0; r < queries.size(); ++r) {
      const uint32_t i = queries[r];
      const std::span<const uint32_t> nb = rows.subspan(r * (k + 1) + 1, k);
      const PcaNormal pca = neighborhood_pca(positions, nb);
      if (pca.degenerate || is_thread(pca, positions, i, nb)) continue;  // no plane to leave
      double c[3] = {0, 0, 0}, spacing = 0;
      std::size_t m = 0;
      for (std::size_t j = 0; j < k; ++j) {
        if (nb[j] == SpatialIndex::kNone) continue;
        for (int a = 0; a < 3; ++a) c[a] += double(positions[nb[j]][a]) - positions[i][a];
        spacing += std::sqrt(double(sq[r * (k + 1) + 1 + j]));
        ++m;
      }
      if (m < 3) continue;
      double h = 0;
      for (int a = 0; a < 3; ++a) h -= double(pca.normal[a]) * c[a] / double(m);
      const double residual = std::sqrt(std::max(0.0, pca.eigenvalues[0]) / double(m));
      const double floor = kPlaneSpacingFloor * spacing / double(m);
      out[i] = std::fabs(h) > std::max(o.sigma * residual, floor);
    }
  });
  return out;
}

template <typename T>
void split(std::vector<T>& values, std::vector<T>& out, const std::vector<uint8_t>& remove) {
  if (values.empty()) return;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (remove[i]) out.push_back(values[i]);
    else values[kept++] = values[i];
  }
  values.resize(kept);
}

void split(ExtraValues& values, ExtraValues& out, const std::vector<uint8_t>& remove) {
  if (values.empty()) return;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (remove[i]) out.push_back(values[i]);
    else values.copy_value(kept++, i);
  }
  values.resize(kept);
}

}  // namespace

nlohmann::json OutlierResult::to_json(const OutlierOptions& o) const {
  if (o.rule == OutlierRule::kStatistical)
    return {{"rule", "sor"}, {"k", o.k}, {"sigma", o.sigma}, {"mean_distance", mean},
            {"stddev", stddev}, {"threshold", threshold}, {"removed", removed}};
  if (o.rule == OutlierRule::kPlane)
    return {{"rule", "plane"}, {"k", o.k}, {"t", o.sigma}, {"removed", removed}};
  return {{"rule", "radius"}, {"radius", radius}, {"min_neighbors", o.min_neighbors},
          {"auto_radius", o.radius == 0}, {"removed", removed}};
}

OutlierResult find_outliers(std::span<const Vec3f> positions, const OutlierOptions& o) {
  OutlierResult r;
  const std::size_t n = positions.size();
  r.outlier.assign(n, 0);
  if (n == 0) return r;
  const SpatialIndex index(positions);
  if (o.rule == OutlierRule::kStatistical) {
    if (n <= o.k) return r;
    const std::vector<float> d = mean_knn_distances(index, o.k);
    double sum = 0, sq_sum = 0;
    for (const float v : d) {
      sum += v;
      sq_sum += static_cast<double>(v * v);  // PCL squares in float
    }
    const double count = static_cast<double>(n);
    r.mean = sum / count;
    r.stddev = std::sqrt((sq_sum - sum * sum / count) / (count - 1));
    r.threshold = r.mean + o.sigma * r.stddev;
    for (std::size_t i = 0; i < n; ++i) r.outlier[i] = d[i] > r.threshold;
  } else if (o.rule == OutlierRule::kPlane) {
    if (n <= o.k) return r;
    r.outlier = off_plane(positions, index, o);
  } else {
    r.radius = o.radius;
    if (r.radius == 0) {
      std::vector<float> d = mean_knn_distances(index, std::min<std::size_t>(8, n - 1));
      if (n > 1) {
        std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(n / 2), d.end());
        r.radius = kAutoRadiusScale * d[n / 2];
      }
    }
    const float radius = static_cast<float>(r.radius);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& range) {
      std::vector<uint32_t> found;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        index.radius(positions[i], radius, found);
        r.outlier[i] = found.size() < o.min_neighbors + 1;  // found includes the point itself
      }
    });
  }
  r.removed = static_cast<std::size_t>(std::count(r.outlier.begin(), r.outlier.end(), 1));
  return r;
}

std::vector<OutlierOptions> default_outlier_passes() {
  std::vector<OutlierOptions> passes = default_statistical_passes();
  OutlierOptions plane;
  plane.rule = OutlierRule::kPlane;
  plane.k = kDefaultPlaneK;
  plane.sigma = kDefaultPlaneT;
  passes.push_back(plane);
  return passes;
}

std::vector<OutlierOptions> default_statistical_passes() {
  std::vector<OutlierOptions> passes(std::size(kDefaultStatisticalK));
  for (std::size_t p = 0; p < passes.size(); ++p) {
    passes[p].k = kDefaultStatisticalK[p];
    passes[p].sigma = kDefaultStatisticalSigma[p];
  }
  return passes;
}

OutlierPassesResult find_outliers(std::span<const Vec3f> positions,
                                  std::span<const OutlierOptions> passes) {
  if (passes.size() > kMaxOutlierPasses)
    throw std::invalid_argument("find_outliers: more than kMaxOutlierPasses passes");
  OutlierPassesResult r;
  r.outlier.assign(positions.size(), 0);
  std::vector<uint32_t> kept(positions.size());  // kept[j]: point j of the current pass's cloud
  for (std::size_t i = 0; i < kept.size(); ++i) kept[i] = static_cast<uint32_t>(i);
  std::vector<Vec3f> cloud(positions.begin(), positions.end());
  for (std::size_t p = 0; p < passes.size(); ++p) {
    OutlierResult pass = find_outliers(cloud, passes[p]);
    std::size_t next = 0;
    for (std::size_t j = 0; j < kept.size(); ++j) {
      if (pass.outlier[j]) {
        r.outlier[kept[j]] = static_cast<uint8_t>(p + 1);
        continue;
      }
      kept[next] = kept[j];
      cloud[next++] = cloud[j];
    }
    kept.resize(next);
    cloud.resize(next);
    r.removed += pass.removed;
    pass.outlier = {};
    r.passes.push_back(std::move(pass));
  }
  return r;
}

nlohmann::json OutlierPassesResult::to_json(std::span<const OutlierOptions> options) const {
  nlohmann::json each = nlohmann::json::array();
  for (std::size_t p = 0; p < passes.size(); ++p) each.push_back(passes[p].to_json(options[p]));
  return {{"removed", removed}, {"passes", each}};
}

SplatCloud split_cloud(SplatCloud& cloud, const std::vector<uint8_t>& remove) {
  SplatCloud out;
  out.origin = cloud.origin;
  out.color_bits = cloud.color_bits;
  out.viewpoint = cloud.viewpoint;
  if (!cloud.face_offsets.empty()) {
    std::vector<uint32_t> renumber(cloud.size());
    uint32_t next = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) renumber[i] = remove[i] ? 0 : next++;
    std::vector<uint32_t> offsets{0}, indices;
    for (std::size_t f = 0; f + 1 < cloud.face_offsets.size(); ++f) {
      const auto b = cloud.face_indices.begin() + cloud.face_offsets[f];
      const auto e = cloud.face_indices.begin() + cloud.face_offsets[f + 1];
      if (std::any_of(b, e, [&](uint32_t v) { return remove[v] != 0; })) continue;
      for (auto it = b; it != e; ++it) indices.push_back(renumber[*it]);
      offsets.push_back(static_cast<uint32_t>(indices.size()));
    }
    cloud.face_offsets = offsets.size() > 1 ? std::move(offsets) : std::vector<uint32_t>{};
    cloud.face_indices = std::move(indices);
  }
  split(cloud.positions, out.positions, remove);
  split(cloud.normals, out.normals, remove);
  split(cloud.radii, out.radii, remove);
  split(cloud.axes, out.axes, remove);
  split(cloud.minor_radii, out.minor_radii, remove);
  split(cloud.colors, out.colors, remove);
  for (ExtraAttribute& e : cloud.extras) {
    out.extras.push_back({e.name, e.type()});
    split(e.values, out.extras.back().values, remove);
  }
  return out;
}

}  // namespace splatkit
