#include "normals/splat_pieces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "normals/bound_radii.h"
#include "normals/pca_normals_and_radii.h"
#include "normals/refit_splats.h"
#include "normals/select_face_normals.h"
#include "normals/widen_flat_normals.h"
#include "splatkit/gathered.h"
#include "splatkit/morton_order.h"
#include "splatkit/spatial_index.h"

namespace splatkit {

namespace {

// The distance from c to the box [lo, hi] (0 inside).
double distance_to_box(const double* c, const double* lo, const double* hi) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({lo[a] - c[a], 0.0, c[a] - hi[a]});
    d2 += d * d;
  }
  return std::sqrt(d2);
}

// The distance between two boxes (0 when they meet).
double distance_between_boxes(const double* lo0, const double* hi0, const double* lo1,
                              const double* hi1) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({lo1[a] - hi0[a], 0.0, lo0[a] - hi1[a]});
    d2 += d * d;
  }
  return std::sqrt(d2);
}

// Cells: a piece's runs of points that share an octree cell, split until they hold at most
// 1/kCellsPerPiece of the piece (kMinCellPoints at least). Each has its own box and halo, so that
// an outlier, or a sparse corner, widens the region of its own cell only.
constexpr std::size_t kCellsPerPiece = 64;
constexpr std::size_t kMinCellPoints = 64;
constexpr double kHaloGrowth = 1.25;
constexpr double kInheritedHaloCap = 4;

}  // namespace

// A piece loaded with its halo: the points within each of its cells' halo of the cell's box, in
// the whole cloud's order.
struct SplatPieces::Local {
  std::vector<uint32_t> ids;                 // whole-cloud numbers, ascending
  std::size_t core_begin = 0, core_end = 0;  // the piece's own points: ids[core_begin, core_end)
  bool whole = false;                        // every point of the cloud is here
  std::vector<Vec3f> positions;
  SpatialIndex index;
  std::vector<uint32_t> cell_of;  // per own point (i - core_begin): its cell within the piece
  std::size_t cells = 0;

  // Per cell of the piece, the halo its own points i with keep(i) need: the ball of squared
  // radius reach[i] around a point lies in its cell's region when the halo is at least its
  // radius (the point is in its cell's box). The radius is widened by a relative 1e-5,
  // far above the rounding of a float squared distance.
  template <class Keep>
  std::vector<double> halo_needed(std::span<const float> reach, Keep&& keep) const {
    std::vector<double> need(cells, 0.0);
    for (std::size_t i = core_begin; i < core_end; ++i) {
      if (!keep(i)) continue;
      const double r = reach[i] < std::numeric_limits<float>::infinity()
                           ? std::sqrt(static_cast<double>(reach[i])) * (1 + 1e-5)
                           : std::numeric_limits<double>::infinity();
      double& n = need[cell_of[i - core_begin]];
      n = std::max(n, r);
    }
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
    return gathered(whole_values, ids);
  }
};

SplatPieces::SplatPieces(std::span<const Vec3f> positions, std::size_t piece_points)
    : positions_(positions) {
  const std::size_t n = positions.size();
  const std::size_t count = std::max<std::size_t>(1, (n + piece_points - 1) / piece_points);
  std::vector<std::size_t> ranges(count + 1);
  for (std::size_t p = 0; p <= count; ++p) ranges[p] = p * n / count;
  const Bounds box = compute_bounds(positions);
  const MortonFrame frame(box.min, box.max);
  const std::size_t cell_points = std::max(kMinCellPoints, piece_points / kCellsPerPiece);
  std::vector<std::vector<Cell>> cells(count);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t p) {
    const std::size_t first = ranges[p];
    std::vector<uint64_t> codes(ranges[p + 1] - first);
    for (std::size_t i = 0; i < codes.size(); ++i) codes[i] = frame.code(positions[first + i]);
    // Splits [b, e) (sharing the codes' top 3d bits) into octree cells of at most cell_points
    // points, or of one code.
    auto split = [&](auto&& self, std::size_t b, std::size_t e, int d) -> void {
      if (e - b <= cell_points || codes[b] == codes[e - 1]) {
        Cell c;
        c.begin = first + b;
        c.end = first + e;
        for (std::size_t i = c.begin; i < c.end; ++i) {
          const double x[3] = {positions[i].x, positions[i].y, positions[i].z};
          for (int a = 0; a < 3; ++a) {
            c.lo[a] = std::min(c.lo[a], x[a]);
            c.hi[a] = std::max(c.hi[a], x[a]);
          }
        }
        cells[p].push_back(c);
        return;
      }
      const int shift = MortonFrame::kCodeBits - 3 * (d + 1);
      for (std::size_t lo = b; lo < e;) {
        const uint64_t octant = codes[lo] >> shift;
        std::size_t hi = lo + 1;
        while (hi < e && codes[hi] >> shift == octant) ++hi;
        self(self, lo, hi, d + 1);
        lo = hi;
      }
    };
    if (!codes.empty()) split(split, 0, codes.size(), 0);
  });
  piece_cells_.push_back(0);
  for (std::size_t p = 0; p < count; ++p) {
    cells_.insert(cells_.end(), cells[p].begin(), cells[p].end());
    piece_cells_.push_back(cells_.size());
  }
  halo_.assign(cells_.size(), 0.0);
  ranges_ = std::move(ranges);
  stats_.pieces = count;
}

SplatPieces::Local SplatPieces::load(std::size_t piece) const {
  Local l;
  const std::size_t first = piece_cells_[piece], last = piece_cells_[piece + 1];
  l.cells = last - first;
  // Per cell t of the cloud: the cells of the piece whose region may reach it.
  std::vector<std::vector<uint32_t>> reach(cells_.size());
  tbb::parallel_for(std::size_t{0}, cells_.size(), [&](std::size_t t) {
    if (t >= first && t < last) return;
    for (std::size_t s = first; s < last; ++s)
      if (distance_between_boxes(cells_[s].lo, cells_[s].hi, cells_[t].lo, cells_[t].hi) <=
          halo_[s])
        reach[t].push_back(static_cast<uint32_t>(s));
  });
  std::vector<std::vector<uint32_t>> found(cells_.size());
  tbb::parallel_for(std::size_t{0}, cells_.size(), [&](std::size_t t) {
    if (reach[t].empty()) return;
    for (std::size_t i = cells_[t].begin; i < cells_[t].end; ++i) {
      const double c[3] = {positions_[i].x, positions_[i].y, positions_[i].z};
      for (uint32_t s : reach[t])
        if (distance_to_box(c, cells_[s].lo, cells_[s].hi) <= halo_[s]) {
          found[t].push_back(static_cast<uint32_t>(i));
          break;
        }
    }
  });
  for (std::size_t t = 0; t < cells_.size(); ++t) {
    if (t == first) {
      l.core_begin = l.ids.size();
      for (std::size_t s = first; s < last; ++s)
        for (std::size_t i = cells_[s].begin; i < cells_[s].end; ++i) {
          l.ids.push_back(static_cast<uint32_t>(i));
          l.cell_of.push_back(static_cast<uint32_t>(s - first));
        }
      l.core_end = l.ids.size();
    }
    l.ids.insert(l.ids.end(), found[t].begin(), found[t].end());
  }
  l.whole = l.ids.size() == positions_.size();
  l.positions = gathered(positions_, l.ids);
  l.index = SpatialIndex(l.positions);
  return l;
}

// Runs attempt(local) on the piece, which returns the halo each of its cells needed, until every
// cell's halo was wide enough (or the load held the whole cloud); returns that last load.
template <class Attempt>
SplatPieces::Local SplatPieces::run(std::size_t piece, Attempt&& attempt) {
  const std::size_t first = piece_cells_[piece], last = piece_cells_[piece + 1];
  // Cells run in order within a phase, so the previous cell's halo is this phase's latest
  // guess; capped at a few times the cell's own from the last phase, so that the wide halo of
  // an outlier's cell does not spread to the cells after it.
  for (std::size_t c = std::max<std::size_t>(first, 1); c < last; ++c) {
    const double own = halo_[c], previous = halo_[c - 1];
    halo_[c] = own > 0 ? std::max(own, std::min(previous, kInheritedHaloCap * own)) : previous;
  }
  for (;;) {
    Local l = load(piece);
    stats_.halo_points += l.ids.size() - (l.core_end - l.core_begin);
    const std::vector<double> need = attempt(l);
    bool enough = true;
    for (std::size_t s = 0; s < need.size(); ++s) {
      if (need[s] <= halo_[first + s]) continue;
      // A rerun costs a whole attempt and a wider halo only its extra points: grow with margin.
      halo_[first + s] = need[s] * kHaloGrowth;
      enough = false;
    }
    if (l.whole || enough) return l;
    ++stats_.reruns;
  }
}

void SplatPieces::normals_and_splats(SplatCloud& cloud, const NormalOptions& o,
                                     NormalReport& report, const ProgressFn& progress,
                                     std::span<uint32_t> head_rows,
                                     std::vector<Bridge>& bridges, std::span<uint8_t> widened,
                                     std::vector<float>& face_cuts) {
  const std::size_t n = positions_.size();
  const std::size_t head = n ? head_rows.size() / n : 0;
  const WholeCloud whole{n, whole_cloud_pca(positions_)};
  std::vector<uint8_t> flags(n, 0);
  auto everything = [](std::size_t) { return true; };
  // Each piece's arrays, reused by the next (and by the refits below): their pages stay mapped (a
  // fresh page costs more than most of the work done on it).
  SplatCloud local;
  std::vector<uint8_t> local_flags;
  std::vector<uint32_t> degenerate, local_rows, local_bridges;
  std::vector<float> reach, wide, ratio;
  std::vector<uint32_t> widen;
  // The face models and λ0 / λ1 of every point, for the choice among the neighbours' models
  // (select_face_normals.h) once every piece has them.
  std::vector<FaceModel> models(n), local_models;
  std::vector<float> ratios(n);
  std::size_t replaced = 0;
  for (std::size_t p = 0; p < pieces(); ++p) {
    DegenerateStats degenerate_stats;
    const Local l = run(p, [&](Local& at) {
      const std::size_t m = at.ids.size();
      local.positions = std::move(at.positions);  // the index holds its own copy
      local.normals.assign(m, Vec3f{0, 0, 1});
      local.radii.assign(m, 0.0f);
      local.axes.assign(o.ellipses ? m : 0, Vec3f{1, 0, 0});
      local.minor_radii.assign(o.ellipses ? m : 0, 0.0f);
      local_flags.assign(m, 0);
      std::vector<float> variation;  // (the robust method's, which pieces do not run)
      ratio.assign(m, 0.0f);
      reach.assign(m, 0.0f);
      wide.assign(m, 0.0f);
      local_rows.resize(m * head);
      local_models.assign(m, FaceModel{});
      pca_normals_and_radii(at.index, local, o, local_flags, variation, reach, no_progress(),
                            local_rows, ratio, local_models);
      degenerate.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (local_flags[i] & kDegenerateFlag) degenerate.push_back(static_cast<uint32_t>(i));
      local_bridges.resize(degenerate.size());
      degenerate_stats =
          resolve_degenerate_normals(at.index, local.positions, degenerate, o.k, o.radius_k,
                                     local.normals, local.radii, &whole, wide, local_bridges);
      for (std::size_t i = 0; i < m; ++i) reach[i] = std::max(reach[i], wide[i]);
      widen.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (!(local_flags[i] & kDegenerateFlag) && ratio[i] > kWidenRatio) {
          widen.push_back(static_cast<uint32_t>(i));
          local_flags[i] |= kOpenCellFlag;  // its splat is refitted to the new normal
        }
      replaced = widen_flat_normals(at.index, local.positions, widen, o.k, local.normals, reach,
                                    local_models);
      return at.halo_needed(reach, everything);
    });
    l.put_back(local.normals, cloud.normals);
    l.put_back(local.radii, cloud.radii);
    l.put_back(local_flags, flags);
    l.put_back(local_models, models);
    l.put_back(ratio, ratios);
    for (std::size_t i = l.core_begin; i < l.core_end; ++i)
      for (std::size_t s = 0; s < head; ++s)
        head_rows[std::size_t{l.ids[i]} * head + s] = l.ids[local_rows[i * head + s]];
    if (o.ellipses) {
      l.put_back(local.axes, cloud.axes);
      l.put_back(local.minor_radii, cloud.minor_radii);
    }
    for (std::size_t d = 0; d < degenerate.size(); ++d)
      if (local_bridges[d] != kNoBridge)
        bridges.push_back({l.ids[degenerate[d]], l.ids[local_bridges[d]]});
    report.degenerate_points += degenerate.size();
    report.widened_points += replaced;
    for (uint32_t i : widen) widened[l.ids[i]] = 1;
    report.unresolved_points += degenerate_stats.unresolved;
    progress(0.15 + 0.45 * static_cast<double>(p + 1) / static_cast<double>(pieces()), "normals");
  }
  select_faces(cloud, o, report, flags, models, ratios, widened, face_cuts);
  std::vector<FaceModel>().swap(models);
  std::vector<float>().swap(ratios);
  if (o.radius_rule != RadiusRule::kCover) return;

  // The refits read the neighbours' final normals, which the first pass wrote for every piece.
  const std::size_t k = kWideRowFactor * row_size(o);
  auto refitted = [&](std::size_t g) { return flags[g] != 0; };  // degenerate or open cell
  for (std::size_t p = 0; p < pieces(); ++p) {
    const auto first = flags.begin() + static_cast<std::ptrdiff_t>(ranges_[p]);
    if (std::all_of(first, first + static_cast<std::ptrdiff_t>(ranges_[p + 1] - ranges_[p]),
                    [](uint8_t f) { return f == 0; }))
      continue;
    std::vector<uint32_t> points;
    const Local l = run(p, [&](Local& at) {
      local.positions = std::move(at.positions);
      local.normals = at.gather(cloud.normals);
      local.radii = at.gather(cloud.radii);
      if (o.ellipses) {
        local.axes = at.gather(cloud.axes);
        local.minor_radii = at.gather(cloud.minor_radii);
      }
      points.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (refitted(at.ids[i])) points.push_back(static_cast<uint32_t>(i));
      reach.assign(at.ids.size(), 0.0f);
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

void SplatPieces::select_faces(SplatCloud& cloud, const NormalOptions& o, NormalReport& report,
                               std::vector<uint8_t>& flags, const std::vector<FaceModel>& models,
                               const std::vector<float>& ratios, std::span<const uint8_t> widened,
                               std::vector<float>& face_cuts) {
  const std::size_t n = positions_.size();
  std::vector<uint32_t> two_layer;
  for (std::size_t i = 0; i < n; ++i)
    if (widened[i]) two_layer.push_back(static_cast<uint32_t>(i));
  for (uint32_t i : two_layer) report.two_face_points += models[i].a != models[i].b;
  if (!thin_parts(report.two_face_points, two_layer.size())) return;
  const float noise = face_noise(models, two_layer);
  std::vector<uint32_t>().swap(two_layer);
  auto blended = [&](std::size_t g) {
    return !(flags[g] & kDegenerateFlag) && ratios[g] > kSelectRatio;
  };
  std::vector<Vec3f> chosen(cloud.normals);  // the neighbours' models read the first normals
  face_cuts.assign(n, std::numeric_limits<float>::quiet_NaN());
  for (std::size_t p = 0; p < pieces(); ++p) {
    std::vector<uint32_t> points;
    std::vector<Vec3f> local_chosen;
    std::vector<float> local_cuts;
    std::size_t changed = 0;
    const Local l = run(p, [&](Local& at) {
      const std::size_t m = at.ids.size();
      const std::vector<Vec3f> normals = at.gather(cloud.normals);
      const std::vector<FaceModel> local_models = at.gather(models);
      points.clear();
      for (std::size_t i = at.core_begin; i < at.core_end; ++i)
        if (blended(at.ids[i])) points.push_back(static_cast<uint32_t>(i));
      local_chosen = normals;
      local_cuts.assign(m, std::numeric_limits<float>::quiet_NaN());
      std::vector<float> reach(m, 0.0f);
      changed = select_face_normals(at.index, at.positions, points, o.k, normals, local_models,
                                    noise, local_chosen, reach, local_cuts);
      return at.halo_needed(reach, [&](std::size_t i) { return blended(at.ids[i]); });
    });
    for (uint32_t i : points) {
      const uint32_t g = l.ids[i];
      if (!(local_chosen[i] == cloud.normals[g])) flags[g] |= kOpenCellFlag;  // refitted below
      chosen[g] = local_chosen[i];
      face_cuts[g] = local_cuts[i];
    }
    report.face_selected += changed;
  }
  cloud.normals.swap(chosen);
  report.face_noise = noise;
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
