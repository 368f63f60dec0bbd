#include "normals/splat_pieces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "normals/bound_radii.h"
#include "normals/pca_normals_and_radii.h"
#include "normals/refit_splats.h"
#include "splatkit/spatial_index.h"

namespace splatkit {

// A piece loaded with its halo: the points of the grown box, in the whole cloud's order.
struct SplatPieces::Local {
  std::vector<uint32_t> ids;                 // whole-cloud numbers, ascending
  std::size_t core_begin = 0, core_end = 0;  // the piece's own points: ids[core_begin, core_end)
  bool whole = false;                        // every point of the cloud is here
  std::vector<Vec3f> positions;
  SpatialIndex index;
  double lo[3], hi[3];  // the piece's own box (not grown)

  // The halo width that puts the ball of squared radius sq around x inside the grown box. The
  // radius is widened by a relative 1e-5, far above the rounding of a float squared distance.
  double halo_for(const Vec3f& x, float sq) const {
    if (!(sq < std::numeric_limits<float>::infinity()))
      return std::numeric_limits<double>::infinity();
    const double r = std::sqrt(static_cast<double>(sq)) * (1 + 1e-5);
    const double c[3] = {x.x, x.y, x.z};
    double need = 0;
    for (int a = 0; a < 3; ++a) need = std::max({need, lo[a] - (c[a] - r), c[a] + r - hi[a]});
    return need;
  }
  // The largest halo_for over the piece's own points i with reach[i] (squared) and keep(i).
  template <class Keep>
  double halo_needed(std::span<const float> reach, Keep&& keep) const {
    double need = 0;
    for (std::size_t i = core_begin; i < core_end; ++i)
      if (keep(i)) need = std::max(need, halo_for(positions[i], reach[i]));
    return need;
  }
  // dst[ids[i]] = src[i] for the piece's own points i.
  template <class T>
  void put_back(const std::vector<T>& src, std::vector<T>& dst) const {
    for (std::size_t i = core_begin; i < core_end; ++i) dst[ids[i]] = src[i];
  }
  // The values of the loaded points.
  template <class T>
  std::vector<T> gather(const std::vector<T>& whole_values) const {
    std::vector<T> out(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) out[i] = whole_values[ids[i]];
    return out;
  }
};

SplatPieces::SplatPieces(std::span<const Vec3f> positions, std::size_t piece_points)
    : positions_(positions) {
  const std::size_t n = positions.size();
  const std::size_t count = std::max<std::size_t>(1, (n + piece_points - 1) / piece_points);
  ranges_.resize(count + 1);
  for (std::size_t p = 0; p <= count; ++p) ranges_[p] = p * n / count;
  lo_.assign(3 * count, std::numeric_limits<double>::infinity());
  hi_.assign(3 * count, -std::numeric_limits<double>::infinity());
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t p) {
    for (std::size_t i = ranges_[p]; i < ranges_[p + 1]; ++i) {
      const double c[3] = {positions[i].x, positions[i].y, positions[i].z};
      for (int a = 0; a < 3; ++a) {
        lo_[3 * p + a] = std::min(lo_[3 * p + a], c[a]);
        hi_[3 * p + a] = std::max(hi_[3 * p + a], c[a]);
      }
    }
  });
  halo_.assign(count, 0.0);
  stats_.pieces = count;
}

SplatPieces::Local SplatPieces::load(std::size_t piece, double halo) const {
  Local l;
  double glo[3], ghi[3];
  for (int a = 0; a < 3; ++a) {
    l.lo[a] = lo_[3 * piece + a];
    l.hi[a] = hi_[3 * piece + a];
    glo[a] = l.lo[a] - halo;
    ghi[a] = l.hi[a] + halo;
  }
  auto inside = [&](const double* plo, const double* phi) {
    for (int a = 0; a < 3; ++a)
      if (phi[a] < glo[a] || plo[a] > ghi[a]) return false;
    return true;
  };
  const std::size_t count = pieces();
  std::vector<std::vector<uint32_t>> found(count);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t q) {
    if (!inside(&lo_[3 * q], &hi_[3 * q])) return;
    for (std::size_t i = ranges_[q]; i < ranges_[q + 1]; ++i) {
      const double c[3] = {positions_[i].x, positions_[i].y, positions_[i].z};
      if (inside(c, c)) found[q].push_back(static_cast<uint32_t>(i));
    }
  });
  for (std::size_t q = 0; q < count; ++q) {
    if (q == piece) l.core_begin = l.ids.size();
    l.ids.insert(l.ids.end(), found[q].begin(), found[q].end());
    if (q == piece) l.core_end = l.ids.size();
  }
  l.whole = l.ids.size() == positions_.size();
  l.positions.resize(l.ids.size());
  for (std::size_t i = 0; i < l.ids.size(); ++i) l.positions[i] = positions_[l.ids[i]];
  l.index = SpatialIndex(l.positions);
  return l;
}

constexpr double kHaloGrowth = 1.25;
constexpr double kInheritedHaloCap = 4;

// Runs attempt(local) on the piece, which returns the halo its queries needed, until the halo
// it ran with was wide enough (or held the whole cloud); returns that last load.
template <class Attempt>
SplatPieces::Local SplatPieces::run(std::size_t piece, Attempt&& attempt) {
  // Pieces run in order within a phase, so the previous piece's halo is this phase's latest
  // guess; capped at a few times the piece's own from the last phase, so that the wide halo of a
  // piece with a far outlier does not spread to the pieces after it.
  if (piece > 0) {
    const double own = halo_[piece], previous = halo_[piece - 1];
    halo_[piece] = own > 0 ? std::max(own, std::min(previous, kInheritedHaloCap * own)) : previous;
  }
  for (;;) {
    Local l = load(piece, halo_[piece]);
    stats_.halo_points += l.ids.size() - (l.core_end - l.core_begin);
    const double need = attempt(l);
    if (l.whole || need <= halo_[piece]) return l;
    // A rerun costs a whole attempt and a wider halo only its extra points: grow with margin.
    halo_[piece] = std::max(need * kHaloGrowth, halo_[piece]);
    ++stats_.reruns;
  }
}

void SplatPieces::normals_and_splats(SplatCloud& cloud, const NormalOptions& o,
                                     NormalReport& report, const ProgressFn& progress) {
  const std::size_t n = positions_.size();
  const WholeCloud whole{n, whole_cloud_pca(positions_)};
  std::vector<uint8_t> flags(n, 0);
  auto everything = [](std::size_t) { return true; };
  for (std::size_t p = 0; p < pieces(); ++p) {
    SplatCloud local;
    std::vector<uint8_t> local_flags;
    std::vector<uint32_t> degenerate;
    DegenerateStats degenerate_stats;
    const Local l = run(p, [&](const Local& at) {
      const std::size_t m = at.ids.size();
      local.positions = at.positions;
      local.normals.assign(m, Vec3f{0, 0, 1});
      local.radii.assign(m, 0.0f);
      local.axes.assign(o.ellipses ? m : 0, Vec3f{1, 0, 0});
      local.minor_radii.assign(o.ellipses ? m : 0, 0.0f);
      local_flags.assign(m, 0);
      std::vector<float> variation, reach(m, 0.0f), wide(m, 0.0f);
      pca_normals_and_radii(at.index, local, o, local_flags, variation, reach, no_progress());
      degenerate.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (local_flags[i] & kDegenerateFlag) degenerate.push_back(static_cast<uint32_t>(i));
      degenerate_stats =
          resolve_degenerate_normals(at.index, local.positions, degenerate, o.k, o.radius_k,
                                     local.normals, local.radii, &whole, wide);
      return std::max(at.halo_needed(reach, everything), at.halo_needed(wide, everything));
    });
    l.put_back(local.normals, cloud.normals);
    l.put_back(local.radii, cloud.radii);
    l.put_back(local_flags, flags);
    if (o.ellipses) {
      l.put_back(local.axes, cloud.axes);
      l.put_back(local.minor_radii, cloud.minor_radii);
    }
    report.degenerate_points += degenerate.size();
    report.unresolved_points += degenerate_stats.unresolved;
    progress(0.15 + 0.45 * static_cast<double>(p + 1) / static_cast<double>(pieces()), "normals");
  }
  if (o.radius_rule != RadiusRule::kCover) return;

  // The refits read the neighbours' final normals, which the first pass wrote for every piece.
  const std::size_t k = kWideRowFactor * row_size(o);
  auto refitted = [&](std::size_t g) { return flags[g] != 0; };  // degenerate or open cell
  for (std::size_t p = 0; p < pieces(); ++p) {
    const auto first = flags.begin() + static_cast<std::ptrdiff_t>(ranges_[p]);
    if (std::all_of(first, first + static_cast<std::ptrdiff_t>(ranges_[p + 1] - ranges_[p]),
                    [](uint8_t f) { return f == 0; }))
      continue;
    SplatCloud local;
    std::vector<uint32_t> points;
    const Local l = run(p, [&](const Local& at) {
      local.positions = at.positions;
      local.normals = at.gather(cloud.normals);
      local.radii = at.gather(cloud.radii);
      if (o.ellipses) {
        local.axes = at.gather(cloud.axes);
        local.minor_radii = at.gather(cloud.minor_radii);
      }
      points.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (refitted(at.ids[i])) points.push_back(static_cast<uint32_t>(i));
      std::vector<float> reach(at.ids.size(), 0.0f);
      refit_splats(at.index, local, o, points, k, reach);
      return at.halo_needed(reach, [&](std::size_t i) { return refitted(at.ids[i]); });
    });
    for (uint32_t i : points) {
      cloud.radii[l.ids[i]] = local.radii[i];
      if (o.ellipses) {
        cloud.axes[l.ids[i]] = local.axes[i];
        cloud.minor_radii[l.ids[i]] = local.minor_radii[i];
      }
    }
    report.refitted_points += points.size();
    progress(0.6 + 0.2 * static_cast<double>(p + 1) / static_cast<double>(pieces()), "splats");
  }
}

std::vector<float> SplatPieces::neighbour_median_radii(const std::vector<float>& radii,
                                                       std::size_t k) {
  std::vector<float> median(radii.size(), 0.0f);
  for (std::size_t p = 0; p < pieces(); ++p) {
    std::vector<float> local;
    const Local l = run(p, [&](const Local& at) {
      std::vector<float> reach(at.ids.size(), 0.0f);
      local = splatkit::neighbour_median_radii(at.index, at.gather(radii), k, reach);
      return at.halo_needed(reach, [](std::size_t) { return true; });
    });
    l.put_back(local, median);
  }
  return median;
}

void SplatPieces::knn_rows(std::size_t k, std::span<uint32_t> out) {
  const std::size_t w = k - 1;
  for (std::size_t p = 0; p < pieces(); ++p) {
    std::vector<uint32_t> rows;  // the piece's own points' rows, in whole-cloud numbers
    run(p, [&](const Local& at) {
      std::vector<float> reach(at.ids.size(), 0.0f);
      rows.assign((at.core_end - at.core_begin) * w, 0);
      at.index.for_each_knn_block(
          k, [&](std::span<const uint32_t> queries, std::span<const uint32_t> indices,
                 std::span<const float> sq_dists) {
            for (std::size_t r = 0; r < queries.size(); ++r) {
              const uint32_t i = queries[r];
              reach[i] = sq_dists[r * k + k - 1];
              if (i < at.core_begin || i >= at.core_end) continue;
              for (std::size_t s = 0; s < w; ++s)
                rows[(i - at.core_begin) * w + s] = at.ids[indices[r * k + 1 + s]];
            }
          });
      return at.halo_needed(reach, [](std::size_t) { return true; });
    });
    std::copy(rows.begin(), rows.end(), out.begin() + static_cast<std::ptrdiff_t>(ranges_[p] * w));
  }
}

}  // namespace splatkit
