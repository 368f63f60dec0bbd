// PCL as the oracle of remove_outliers: on clouds with injected outliers, PCL 1.13's
// StatisticalOutlierRemoval and RadiusOutlierRemoval (the same K, SIGMA, R, N) must remove exactly
// the points find_outliers marks; chained passes must remove exactly the points PCL's filters
// remove when each is run on the previous one's output. Prints one line per case; exits 1 on any
// difference.
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <string>
#include <vector>

#include "normals/remove_outliers.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/synthetic_shapes.h"

namespace {

using splatkit::OutlierOptions;
using splatkit::OutlierRule;

std::vector<splatkit::Vec3f> scan(splatkit::ShapeKind kind, std::size_t n, double noise,
                                  uint64_t seed, double scan_lines) {
  splatkit::ShapeOptions s;
  s.kind = kind;
  s.points = n;
  s.seed = seed;
  s.noise = noise;
  s.random = true;
  s.scan_lines = scan_lines;
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

// PCL's filters run in turn, each on the cloud the previous one output: 1 = removed by any.
std::vector<uint8_t> pcl_outliers(const std::vector<splatkit::Vec3f>& p,
                                  const std::vector<OutlierOptions>& passes) {
  std::vector<uint8_t> out(p.size(), 0);
  std::vector<std::size_t> kept(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) kept[i] = i;
  std::vector<splatkit::Vec3f> cloud = p;
  for (const OutlierOptions& o : passes) {
    const std::vector<uint8_t> removed = pcl_outliers(cloud, o);
    std::vector<std::size_t> next_kept;
    std::vector<splatkit::Vec3f> next_cloud;
    for (std::size_t j = 0; j < cloud.size(); ++j) {
      if (removed[j]) {
        out[kept[j]] = 1;
      } else {
        next_kept.push_back(kept[j]);
        next_cloud.push_back(cloud[j]);
      }
    }
    kept = std::move(next_kept);
    cloud = std::move(next_cloud);
  }
  return out;
}

OutlierOptions sor(std::size_t k, double sigma) {
  OutlierOptions o;
  o.k = k;
  o.sigma = sigma;
  return o;
}

}  // namespace

int main() {
  int failures = 0;
  struct Case {
    splatkit::ShapeKind kind;
    std::size_t n;
    double noise;
    uint64_t seed;
    double scan_lines;
  };
  const Case cases[] = {{splatkit::ShapeKind::kCadPart, 30000, 0, 1, 0},
                        {splatkit::ShapeKind::kTorus, 30000, 0.002, 2, 0},
                        {splatkit::ShapeKind::kSphere, 20000, 0.001, 3, 0},
                        {splatkit::ShapeKind::kCadPart, 40000, 0, 1, 4}};
  for (const Case& c : cases) {
    const std::vector<splatkit::Vec3f> p = scan(c.kind, c.n, c.noise, c.seed, c.scan_lines);
    std::vector<OutlierOptions> variants{OutlierOptions{}};  // sor:12,1
    for (auto [k, sigma] :
         {std::pair<std::size_t, double>{8, 1.0}, {16, 2.0}, {30, 0.5}, {6, 0.4}}) {
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
    // Chained passes: the defaults (a loose pass then a tighter one); sor:12,1 twice; three
    // passes; radius then sor.
    OutlierOptions radius;
    radius.rule = OutlierRule::kRadius;
    radius.radius = r;
    const std::vector<std::vector<OutlierOptions>> chains = {splatkit::default_statistical_passes(),
                                                             {OutlierOptions{}, OutlierOptions{}},
                                                             {sor(16, 2), sor(8, 2), sor(8, 2)},
                                                             {radius, sor(12, 1)}};
    for (const std::vector<OutlierOptions>& chain : chains) {
      const splatkit::OutlierPassesResult ours = splatkit::find_outliers(p, chain);
      const std::vector<uint8_t> theirs = pcl_outliers(p, chain);
      std::size_t differ = 0, pcl_removed = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        differ += (ours.outlier[i] != 0) != (theirs[i] != 0);
        pcl_removed += theirs[i];
      }
      std::string name;
      for (const OutlierOptions& o : chain) {
        char pass[64];
        if (o.rule == OutlierRule::kStatistical)
          std::snprintf(pass, sizeof pass, "sor:%zu,%g", o.k, o.sigma);
        else
          std::snprintf(pass, sizeof pass, "radius:%g,%zu", o.radius, o.min_neighbors);
        name += (name.empty() ? "" : "+") + std::string(pass);
      }
      std::string per_pass;
      for (const splatkit::OutlierResult& pass : ours.passes)
        per_pass += (per_pass.empty() ? "" : "+") + std::to_string(pass.removed);
      std::printf("%s %zu points: %s: splatkit removes %zu (%s), PCL %zu, %zu differ\n",
                  splatkit::shape_kind_name(c.kind).c_str(), p.size(), name.c_str(), ours.removed,
                  per_pass.c_str(), pcl_removed, differ);
      if (differ || ours.passes.size() != chain.size()) ++failures;
    }
  }
  return failures ? 1 : 0;
}
