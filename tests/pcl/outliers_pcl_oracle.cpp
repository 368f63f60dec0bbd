// PCL as the oracle of remove_outliers: on clouds with injected outliers, PCL 1.13's
// StatisticalOutlierRemoval and RadiusOutlierRemoval (the same K, SIGMA, R, N) must remove exactly
// the points find_outliers marks. Prints one line per case; exits 1 on any difference.
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <vector>

#include "normals/remove_outliers.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/synthetic_shapes.h"

namespace {

using splatkit::OutlierOptions;
using splatkit::OutlierRule;

std::vector<splatkit::Vec3f> scan(splatkit::ShapeKind kind, std::size_t n, double noise, uint64_t seed) {
  splatkit::ShapeOptions s;
  s.kind = kind;
  s.points = n;
  s.seed = seed;
  s.noise = noise;
  s.random = true;
  std::vector<splatkit::Vec3f> p = splatkit::make_shape(s).positions;
  splatkit::Bounds b;
  b.min = b.max = p.front();
  for (const auto& q : p) {
    b.min = {std::min(b.min.x, q.x), std::min(b.min.y, q.y), std::min(b.min.z, q.z)};
    b.max = {std::max(b.max.x, q.x), std::max(b.max.y, q.y), std::max(b.max.z, q.z)};
  }
  splatkit::DeterministicRng rng(seed + 1000);
  for (std::size_t i = 0, extra = p.size() / 100; i < extra; ++i)
    p.push_back({static_cast<float>(rng.uniform(b.min.x, b.max.x)),
                 static_cast<float>(rng.uniform(b.min.y, b.max.y)),
                 static_cast<float>(rng.uniform(b.min.z, b.max.z))});
  return p;
}

std::vector<uint8_t> pcl_outliers(const std::vector<splatkit::Vec3f>& p, const OutlierOptions& o) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& q : p) cloud->push_back({q.x, q.y, q.z});
  pcl::Indices kept;
  if (o.rule == OutlierRule::kStatistical) {
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> f;
    f.setInputCloud(cloud);
    f.setMeanK(static_cast<int>(o.k));
    f.setStddevMulThresh(o.sigma);
    f.filter(kept);
  } else {
    pcl::RadiusOutlierRemoval<pcl::PointXYZ> f;
    f.setInputCloud(cloud);
    f.setRadiusSearch(o.radius);
    f.setMinNeighborsInRadius(static_cast<int>(o.min_neighbors));
    f.filter(kept);
  }
  std::vector<uint8_t> out(p.size(), 1);
  for (const auto i : kept) out[static_cast<std::size_t>(i)] = 0;
  return out;
}

}  // namespace

int main() {
  int failures = 0;
  struct Case {
    splatkit::ShapeKind kind;
    std::size_t n;
    double noise;
    uint64_t seed;
  };
  const Case cases[] = {{splatkit::ShapeKind::kCadPart, 30000, 0, 1},
                        {splatkit::ShapeKind::kTorus, 30000, 0.002, 2},
                        {splatkit::ShapeKind::kSphere, 20000, 0.001, 3}};
  for (const Case& c : cases) {
    const std::vector<splatkit::Vec3f> p = scan(c.kind, c.n, c.noise, c.seed);
    std::vector<OutlierOptions> variants;
    for (auto [k, sigma] : {std::pair<std::size_t, double>{8, 1.0}, {16, 2.0}, {30, 0.5}}) {
      OutlierOptions o;
      o.k = k;
      o.sigma = sigma;
      variants.push_back(o);
    }
    OutlierOptions automatic;
    automatic.rule = OutlierRule::kRadius;
    const double r = splatkit::find_outliers(p, automatic).radius;
    for (auto [scale, n] : {std::pair<double, std::size_t>{1.0, 6}, {0.7, 3}, {1.5, 12}}) {
      OutlierOptions o;
      o.rule = OutlierRule::kRadius;
      o.radius = r * scale;
      o.min_neighbors = n;
      variants.push_back(o);
    }
    for (const OutlierOptions& o : variants) {
      const splatkit::OutlierResult ours = splatkit::find_outliers(p, o);
      const std::vector<uint8_t> theirs = pcl_outliers(p, o);
      std::size_t differ = 0, pcl_removed = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        differ += ours.outlier[i] != theirs[i];
        pcl_removed += theirs[i];
      }
      const bool sor = o.rule == OutlierRule::kStatistical;
      std::printf("%s %zu points: %s %g,%g: splatkit removes %zu, PCL %zu, %zu differ\n",
                  splatkit::shape_kind_name(c.kind).c_str(), p.size(), sor ? "sor" : "radius",
                  sor ? static_cast<double>(o.k) : o.radius,
                  sor ? o.sigma : static_cast<double>(o.min_neighbors), ours.removed, pcl_removed,
                  differ);
      if (differ) ++failures;
    }
  }
  return failures ? 1 : 0;
}
