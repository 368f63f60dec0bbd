#include "apps/check_tile_halo.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "apps/tile_square.h"
#include "splatkit/spatial_index.h"
#include "splatkit/take_own_points.h"
#include "splatkit/tile_halo.h"

namespace splatkit::apps {

nlohmann::json TileHaloCheck::to_json() const {
  if (!tile) return nullptr;
  return {{"halo", halo}, {"points_checked", checked}, {"points_short", short_of},
          {"halo_needed", needed}};
}

TileHaloCheck check_tile_halo(const nlohmann::json& metadata, const SplatCloud& cloud) {
  TileHaloCheck check;
  const std::optional<TileSquare> tile = tile_square(metadata);
  if (!tile) return check;
  check.tile = true;
  check.halo = tile->halo;
  const std::size_t n = cloud.size();
  if (n < kTileHaloRow) return check;
  bool open[4];
  for (int s = 0; s < 4; ++s) open[s] = survey_goes_on(*tile, s);
  if (!(open[0] || open[1] || open[2] || open[3])) return check;
  const ExtraAttribute* halo_flag = cloud.find_extra(kHaloAttribute);
  // Signed distance in plan from a point to the nearest side the survey goes on past: negative
  // beyond it (a halo point). What the tile lacks lies beyond inset -halo.
  const double inf = std::numeric_limits<double>::infinity();
  auto inset = [&](const Vec3f& p) {
    const double x = p.x + cloud.origin[0], y = p.y + cloud.origin[1];
    const double d[4] = {x - tile->lo[0], tile->hi[0] - x, y - tile->lo[1], tile->hi[1] - y};
    double m = inf;
    for (int s = 0; s < 4; ++s)
      if (open[s]) m = std::min(m, d[s]);
    return m;
  };
  // The own points within one halo of an open side are checked, over an index of the points
  // within four: a checked point whose 64 nearest lie within its inset plus the halo (at most two
  // halos) finds them all in the index (and one whose 64th lies farther is short whatever the
  // index holds), and its row's points find their 32 nearest there unless they reach past three
  // halos (then the index, short of some, can only overstate their reach).
  const double halo = tile->halo, band = halo, indexed = 4 * halo;
  std::vector<uint32_t> ids;
  std::vector<Vec3f> near;
  std::vector<double> near_inset;
  for (std::size_t i = 0; i < n; ++i) {
    const double in = inset(cloud.positions[i]);
    if (in < indexed) {
      ids.push_back(static_cast<uint32_t>(i));
      near.push_back(cloud.positions[i]);
      near_inset.push_back(in);
    }
  }
  if (near.size() < kTileHaloRow) return check;
  const SpatialIndex index(near);
  constexpr std::size_t kInnerRow = kTileHaloRow / 2;
  struct Sum {
    std::size_t checked = 0, short_of = 0;
    double needed = 0;
  };
  const Sum sum = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, ids.size(), 4096), Sum{},
      [&](const tbb::blocked_range<std::size_t>& r, Sum s) {
        uint32_t row[kTileHaloRow], inner[kInnerRow];
        float sq[kTileHaloRow], inner_sq[kInnerRow];
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          if (halo_flag != nullptr && halo_flag->values[ids[k]] != 0) continue;
          const double in = near_inset[k];
          if (!(in >= 0 && in < band)) continue;
          ++s.checked;
          if (index.knn(near[k], kTileHaloRow, row, sq) < kTileHaloRow) continue;
          const double d64 = std::sqrt(static_cast<double>(sq[kTileHaloRow - 1]));
          // Each row's reach past the tile: the point's own 64-row, and each of its points'
          // 32-row (at most its distance plus d64; measured where that bound passes the halo).
          double past = d64 - in;
          if (2 * d64 > in + halo)
            for (std::size_t m = 0; m < kTileHaloRow; ++m) {
              const double at = std::sqrt(static_cast<double>(sq[m]));
              const double in_m = near_inset[row[m]];
              if (at + d64 - in_m <= halo) continue;
              const std::size_t g = index.knn(near[row[m]], kInnerRow, inner, inner_sq);
              past = std::max(past, std::sqrt(static_cast<double>(inner_sq[g - 1])) - in_m);
            }
          if (past > halo) {
            ++s.short_of;
            s.needed = std::max(s.needed, past);
          }
        }
        return s;
      },
      [](Sum a, const Sum& b) {
        a.checked += b.checked;
        a.short_of += b.short_of;
        a.needed = std::max(a.needed, b.needed);
        return a;
      });
  check.checked = sum.checked;
  check.short_of = sum.short_of;
  check.needed = sum.needed;
  return check;
}

}  // namespace splatkit::apps
