// remove_outliers: the two classic outlier filters of point-cloud tools, with PCL's semantics
// ([Rusu08], docs/references.md; PCL's StatisticalOutlierRemoval and RadiusOutlierRemoval,
// CloudCompare's SOR and ROR tools):
//
//  - statistical (sor): d_i = mean distance from point i to its K nearest other points (in double,
//    stored as float); mean m and sample standard deviation s of all d_i (double sums in index
//    order); point i is an outlier iff d_i > m + SIGMA * s.
//  - radius: point i is an outlier iff fewer than N other points lie within distance R of it
//    (squared distance <= R * R, in float).
//
// Passes: the filters can be chained, each applied to the points the previous passes kept, with
// its own statistics over those points only (PCL's filter run again on its own output). A first
// statistical pass removes the far outliers that inflate the standard deviation; a second one,
// whose mean and deviation then describe the scan, reaches nearer ones (scripts/bench/
// outliers.sh: sor:12,3 then sor:6,3.5 removes 87.6 % of injected outliers on average over its
// 11 scans, against 84.4 % for sor:12,1 alone, at up to 0.22 % of a scan's own points against
// 0.05 %; neither reaches the points within about 1.5 sampling spacings of the surface).
//
// Positions are the cloud's (local frame, finite). A cloud of at most K points is left whole
// (statistical). Deterministic: the result does not depend on the thread count. Cost: one kNN pass
// (K + 1 per row, streamed) or one fixed-radius query per point, in parallel (TBB).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "splatkit/splat_cloud.h"

namespace splatkit {

enum class OutlierRule { kStatistical, kRadius };

struct OutlierOptions {
  OutlierRule rule = OutlierRule::kStatistical;
  // Defaults chosen by measurement (scripts/bench/outliers.sh: 1 % of the point count injected
  // uniformly in the bounding box of 11 scans, synthetic and real; s = the square root of the
  // scan's area per point): k = 12, sigma = 1 is the only cell of the K x SIGMA grid that removes
  // at most 0.5 % of every scan's own points (at most 0.05 %); it removes 70-95 % of the injected
  // points (84 % on average; k = 8, sigma = 1 removes 1 % more but 0.52 % of a 40 000-point scan
  // with scan lines; sigma = 0.75, 2 % more but 0.6-0.7 % of some scans). It removes every
  // injected point farther than 3-5 s from the scan and none within 1 s: those lie in the
  // surface's own sampling and noise band, and their share (5-30 % within 1.5 s, depending on
  // how much surface the box holds at that density) decides the total. SIGMA multiplies a
  // deviation that the outliers themselves inflate (1 % of the points, tens of s away), so the
  // threshold in units of s grows with the scan's density.
  std::size_t k = 12;       // statistical: neighbours averaged (>= 1)
  double sigma = 1.0;       // statistical: standard deviations above the mean (finite)
  double radius = 0;        // radius rule: R in the cloud's units; 0 = automatic (see below)
  std::size_t min_neighbors = 6;  // radius rule: N
};
// The automatic R of the radius rule: kAutoRadiusScale times the median, over the cloud, of the
// mean distance to the 8 nearest other points (about 1.5 sampling spacings). Measured as above:
// 2x with N = 6 removes 99-100 % of the injected points farther than 2 spacings and at most 0.2 %
// of the true points (1x loses 1 in 4 true points; 1.5x, N = 4, 2-3 %).
inline constexpr double kAutoRadiusScale = 2.0;

struct OutlierResult {
  std::vector<uint8_t> outlier;  // #N, 1 = outlier
  std::size_t removed = 0;
  // statistical: mean, standard deviation and threshold of d_i; radius: the R used.
  double mean = 0, stddev = 0, threshold = 0, radius = 0;
  nlohmann::json to_json(const OutlierOptions& options) const;
};

OutlierResult find_outliers(std::span<const Vec3f> positions, const OutlierOptions& options);

// Up to kMaxOutlierPasses passes, in order, each over the points the previous ones kept.
inline constexpr std::size_t kMaxOutlierPasses = 8;
struct OutlierPassesResult {
  std::vector<uint8_t> outlier;  // #N: 0 = kept, p = removed by pass p (1-based)
  std::size_t removed = 0;       // by all passes
  std::vector<OutlierResult> passes;  // each pass's statistics and count (its `outlier` emptied)
  // {"removed": all passes, "passes": [each pass as OutlierResult::to_json]}
  nlohmann::json to_json(std::span<const OutlierOptions> options) const;
};
OutlierPassesResult find_outliers(std::span<const Vec3f> positions,
                                  std::span<const OutlierOptions> passes);

// Moves the points marked in `remove` (#N) out of `cloud` into the returned cloud (same origin,
// same attributes, relative order kept in both). Faces that use a removed point are dropped; the
// others are renumbered.
SplatCloud split_cloud(SplatCloud& cloud, const std::vector<uint8_t>& remove);

}  // namespace splatkit
