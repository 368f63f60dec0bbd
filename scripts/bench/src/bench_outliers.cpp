// Outlier removal measured (outliers.sh): a scan read from FILE gets 1 % of its point count added
// uniformly in its bounding box; then, over a grid of K and SIGMA, the share of those injected
// points that `sor` removes and the share of the scan's own points it removes (PCL's
// StatisticalOutlierRemoval rule, computed as in lib/normals/remove_outliers.cpp; the default
// cell is also run through find_outliers itself), the same for a robust threshold (median +
// KAPPA * 1.4826 * MAD of the same distances), and the injected points by their distance to the
// nearest scan point in s, the square root of the scan's area per point: the ones lying on the
// surface are not outliers any rule can see. Then iterated SOR over a grid of first passes and
// later passes (each pass PCL's rule over the previous pass's survivors).
//
// usage: bench_outliers NAME FILE [SEED=1] [DEFAULT_K=8] [DEFAULT_SIGMA=1] [CELLS.tsv] [CHAIN]
//   prints text tables (see outliers.sh); with CELLS.tsv, appends one line per grid cell:
//   NAME RULE K PARAMETER injected% scan% (for the summary over scans); with CHAIN
//   ("K1,SIGMA1+K2,SIGMA2..."), also runs those passes through find_outliers.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "normals/remove_outliers.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"

using namespace splatkit;

namespace {

const std::size_t kKs[] = {4, 6, 8, 12, 16, 24, 32, 48};
const double kSigmas[] = {-0.25, 0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.75, 1, 1.5, 2, 3};
const double kKappas[] = {2, 3, 4, 5, 6, 8, 10};
const double kBands[] = {0, 0.5, 1, 1.5, 2, 3, 5, 10, 1e300};  // spacings

double median(std::vector<float> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

struct Scores {
  double outliers_pct = 0, true_pct = 0;
  std::vector<std::size_t> band_removed;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_outliers NAME FILE [SEED] [DEFAULT_K] [DEFAULT_SIGMA]\n");
    return 1;
  }
  const std::string name = argv[1];
  const uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  const std::size_t default_k = argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 8;
  const double default_sigma = argc > 5 ? std::strtod(argv[5], nullptr) : 1.0;
  FILE* cells = argc > 6 ? std::fopen(argv[6], "a") : nullptr;

  std::vector<Vec3f> p = read_cloud(argv[2]).cloud.positions;
  const std::size_t n_true = p.size();
  Vec3f lo = p.front(), hi = p.front();
  for (const Vec3f& q : p) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
  DeterministicRng rng(seed);
  const std::size_t n_out = n_true / 100;
  for (std::size_t i = 0; i < n_out; ++i)
    p.push_back({static_cast<float>(rng.uniform(lo.x, hi.x)),
                 static_cast<float>(rng.uniform(lo.y, hi.y)),
                 static_cast<float>(rng.uniform(lo.z, hi.z))});
  const std::size_t n = p.size();

  // Spacing s = the square root of the scan's area per point, from the median distance r8 to the
  // 8th nearest scan point (a disc of radius r8 holds 8 points: s = r8 * sqrt(pi / 8)); robust to
  // scan lines, where the nearest neighbour is along the line. Each injected point's distance to
  // the nearest scan point, in s.
  const SpatialIndex scan_index(std::span<const Vec3f>(p.data(), n_true));
  std::vector<float> r8(n_true);
  scan_index.for_each_knn_block(
      9, [&](std::span<const uint32_t> q, std::span<const uint32_t>, std::span<const float> sq) {
        for (std::size_t r = 0; r < q.size(); ++r) r8[q[r]] = std::sqrt(sq[r * 9 + 8]);
      });
  const double spacing = median(r8) * std::sqrt(3.14159265358979 / 8);
  std::vector<double> off(n_out);
  std::vector<std::size_t> band_count(std::size(kBands) - 1, 0);
  auto band_of = [&](double d) {
    std::size_t b = 0;
    while (b + 2 < std::size(kBands) && d >= kBands[b + 1]) ++b;
    return b;
  };
  for (std::size_t i = 0; i < n_out; ++i) {
    uint32_t idx;
    float sq;
    scan_index.knn(p[n_true + i], 1, &idx, &sq);
    off[i] = std::sqrt(double(sq)) / spacing;
    ++band_count[band_of(off[i])];
  }

  // Mean distance to the K nearest other points, for every K of the grid, from one kNN pass
  // (the same sums as find_outliers: double over sqrt of the float squared distances).
  const std::size_t kmax = kKs[std::size(kKs) - 1];
  const SpatialIndex index(p);
  std::vector<std::vector<float>> d(std::size(kKs), std::vector<float>(n));
  index.for_each_knn_block(kmax + 1, [&](std::span<const uint32_t> q, std::span<const uint32_t>,
                                         std::span<const float> sq) {
    for (std::size_t r = 0; r < q.size(); ++r) {
      double sum = 0;
      std::size_t next = 0;
      for (std::size_t j = 1; j <= kmax; ++j) {
        sum += std::sqrt(sq[r * (kmax + 1) + j]);
        if (j == kKs[next]) d[next++][q[r]] = static_cast<float>(sum / static_cast<double>(j));
      }
    }
  });

  // The shares of the injected points and of the scan's own points that `removed(i)` takes.
  auto score_removed = [&](auto&& removed) {
    Scores s;
    s.band_removed.assign(band_count.size(), 0);
    std::size_t lost = 0, found = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!removed(i)) continue;
      if (i < n_true) {
        ++lost;
      } else {
        ++found;
        ++s.band_removed[band_of(off[i - n_true])];
      }
    }
    s.outliers_pct = 100.0 * double(found) / double(n_out);
    s.true_pct = 100.0 * double(lost) / double(n_true);
    return s;
  };
  auto score = [&](const std::vector<float>& dk, double threshold) {
    return score_removed([&](std::size_t i) { return dk[i] > threshold; });
  };
  auto sor_threshold = [&](const std::vector<float>& dk, double sigma) {
    double sum = 0, sq_sum = 0;
    for (const float v : dk) {
      sum += v;
      sq_sum += static_cast<double>(v * v);
    }
    const double count = static_cast<double>(n);
    return sum / count + sigma * std::sqrt((sq_sum - sum * sum / count) / (count - 1));
  };
  auto robust_threshold = [&](const std::vector<float>& dk, double kappa) {
    const double m = median(dk);
    std::vector<float> dev(dk.size());
    for (std::size_t i = 0; i < dk.size(); ++i) dev[i] = static_cast<float>(std::abs(dk[i] - m));
    return m + kappa * 1.4826 * median(dev);
  };

  std::printf("== %s: %zu scan points + %zu injected (1 %%, uniform in the box), s = %.4g\n",
              name.c_str(), n_true, n_out, spacing);
  std::printf("injected points by distance to the nearest scan point (in s):");
  for (std::size_t b = 0; b < band_count.size(); ++b) {
    if (b + 2 < std::size(kBands))
      std::printf("  %g-%g: %.1f%%", kBands[b], kBands[b + 1],
                  100.0 * double(band_count[b]) / double(n_out));
    else
      std::printf("  >=%g: %.1f%%", kBands[b], 100.0 * double(band_count[b]) / double(n_out));
  }
  std::printf("\n");
  // No distance rule sees a point within about 1 s of the nearest scan point: a point on the
  // surface, between samples, lies up to 0.7 s from the nearest one (square grid; more on random
  // or scan-line sampling), and the noise band adds to that. The share beyond 1 s is the most a
  // rule can remove without removing the surface's own sampling.
  double beyond1 = 0;
  for (std::size_t b = 0; b < band_count.size(); ++b)
    if (kBands[b] >= 1) beyond1 += 100.0 * double(band_count[b]) / double(n_out);
  std::printf("ceiling: %.1f %% of the injected points lie 1 s or more from the scan\n", beyond1);
  if (cells) std::fprintf(cells, "%s\tceiling\t0\t1\t%.3f\t0\n", name.c_str(), beyond1);

  struct Best {
    std::string rule;
    Scores s;
  } best{"none", {}};
  auto consider = [&](const std::string& rule, const Scores& s) {
    if (s.true_pct <= 0.5 && s.outliers_pct > best.s.outliers_pct) best = {rule, s};
  };
  // One table: K rows, parameter columns; each cell scored, printed, considered and logged.
  auto table = [&](const char* rule, std::span<const double> params, std::size_t digits,
                   auto&& threshold) {
    for (double v : params) std::printf(" %12g", v);
    std::printf("\n");
    for (std::size_t ki = 0; ki < std::size(kKs); ++ki) {
      std::printf("%4zu", kKs[ki]);
      for (double v : params) {
        const Scores s = score(d[ki], threshold(d[ki], v));
        std::printf(" %5.1f/%-6.2f", s.outliers_pct, s.true_pct);
        consider(std::string(rule) + ":" + std::to_string(kKs[ki]) + "," +
                     std::to_string(v).substr(0, digits),
                 s);
        if (cells)
          std::fprintf(cells, "%s\t%s\t%zu\t%g\t%.3f\t%.4f\n", name.c_str(), rule, kKs[ki], v,
                       s.outliers_pct, s.true_pct);
      }
      std::printf("\n");
    }
  };
  std::printf("sor: injected removed %% / scan points removed %% (K rows, SIGMA columns)\n   K");
  table("sor", kSigmas, 5, sor_threshold);
  std::printf(
      "robust (median + KAPPA * 1.4826 MAD): removed %% / scan %% (K rows, KAPPA columns)\n   K");
  table("robust", kKappas, 4, robust_threshold);
  // The share of each distance band that a rule removed.
  auto band_list = [&](const Scores& s) {
    for (std::size_t b = 0; b < band_count.size(); ++b)
      if (band_count[b])
        std::printf("  %g-: %.0f%%", kBands[b],
                    100.0 * double(s.band_removed[b]) / double(band_count[b]));
    std::printf("\n");
  };
  auto print_bands = [&](const Scores& s) {
    if (s.band_removed.empty()) return;
    std::printf("  removed per distance band:");
    band_list(s);
  };
  std::printf(
      "best with <= 0.5 %% of the scan removed: %s removes %.1f %% of the injected points "
      "(%.2f %% of the scan)\n",
      best.rule.c_str(), best.s.outliers_pct, best.s.true_pct);
  print_bands(best.s);

  // Iterated SOR: PCL's filter applied again to its own output. A first pass (K1, SIGMA1)
  // removes the far outliers that inflate the standard deviation; the later passes (K2, SIGMA2),
  // each over the previous pass's survivors with their own mean and deviation, see the scan.
  // Each cell is "K1,SIGMA1+K2,SIGMA2" (2 passes) or "K1,SIGMA1+K2,SIGMA2x2" (3 passes, the
  // last two alike).
  struct IterBest {
    std::string cell;
    Scores s;
  } iter_best{"none", {}};
  {
    // Mean distance to the K nearest other points of `alive` (indices into p), for every K of
    // kK2s, over the cloud made of those points only.
    const std::size_t kK2s[] = {6, 8, 12, 16, 24};
    const double kSigma2s[] = {1, 1.5, 2, 2.5, 3, 3.5, 4, 5};
    auto knn_means = [&](const std::vector<uint32_t>& alive) {
      std::vector<Vec3f> q(alive.size());
      for (std::size_t i = 0; i < alive.size(); ++i) q[i] = p[alive[i]];
      const std::size_t km = kK2s[std::size(kK2s) - 1];
      std::vector<std::vector<float>> dk(std::size(kK2s), std::vector<float>(q.size()));
      const SpatialIndex idx(q);
      idx.for_each_knn_block(km + 1, [&](std::span<const uint32_t> qs, std::span<const uint32_t>,
                                         std::span<const float> sq) {
        for (std::size_t r = 0; r < qs.size(); ++r) {
          double sum = 0;
          std::size_t next = 0;
          for (std::size_t j = 1; j <= km; ++j) {
            sum += std::sqrt(sq[r * (km + 1) + j]);
            if (j == kK2s[next]) dk[next++][qs[r]] = static_cast<float>(sum / double(j));
          }
        }
      });
      return dk;
    };
    auto threshold_of = [](const std::vector<float>& dk, double sigma) {
      double sum = 0, sq_sum = 0;
      for (const float v : dk) {
        sum += v;
        sq_sum += static_cast<double>(v * v);
      }
      const double count = static_cast<double>(dk.size());
      return sum / count + sigma * std::sqrt((sq_sum - sum * sum / count) / (count - 1));
    };
    auto score_alive = [&](const std::vector<uint32_t>& alive) {
      std::vector<uint8_t> removed(n, 1);
      for (uint32_t i : alive) removed[i] = 0;
      return score_removed([&](std::size_t i) { return removed[i] != 0; });
    };
    auto filter = [](const std::vector<uint32_t>& alive, const std::vector<float>& dk, double t) {
      std::vector<uint32_t> out;
      for (std::size_t i = 0; i < alive.size(); ++i)
        if (!(dk[i] > t)) out.push_back(alive[i]);
      return out;
    };
    const std::size_t kK1s[] = {8, 12, 16};
    const double kSigma1s[] = {1, 2, 3};
    std::printf(
        "iterated sor (PCL's filter on its own output): injected removed %% / scan removed %%\n"
        "  first pass K1,SIGMA1; rows K2 of the later passes, SIGMA2 columns; 2 passes, then 3\n");
    for (std::size_t k1 = 0; k1 < std::size(kKs); ++k1) {
      if (std::find(std::begin(kK1s), std::end(kK1s), kKs[k1]) == std::end(kK1s)) continue;
      for (const double s1 : kSigma1s) {
        std::vector<uint32_t> all(n);
        for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<uint32_t>(i);
        const std::vector<uint32_t> alive1 = filter(all, d[k1], sor_threshold(d[k1], s1));
        const auto d2 = knn_means(alive1);
        for (int passes = 2; passes <= 3; ++passes) {
          std::printf("  %zu,%g then %s  K2", kKs[k1], s1, passes == 2 ? "1 pass" : "2 passes");
          for (const double s2 : kSigma2s) std::printf(" %12g", s2);
          std::printf("\n");
          for (std::size_t k2 = 0; k2 < std::size(kK2s); ++k2) {
            std::printf("  %26zu", kK2s[k2]);
            for (const double s2 : kSigma2s) {
              std::vector<uint32_t> alive = filter(alive1, d2[k2], threshold_of(d2[k2], s2));
              if (passes == 3) {
                const auto d3 = knn_means(alive);
                alive = filter(alive, d3[k2], threshold_of(d3[k2], s2));
              }
              const Scores s = score_alive(alive);
              std::printf(" %5.1f/%-6.3f", s.outliers_pct, s.true_pct);
              char cell[64];
              std::snprintf(cell, sizeof cell, "%zu,%g+%zu,%g%s", kKs[k1], s1, kK2s[k2], s2,
                            passes == 3 ? "x2" : "");
              if (s.true_pct <= 0.5 && s.outliers_pct > iter_best.s.outliers_pct)
                iter_best = {cell, s};
              if (cells)
                std::fprintf(cells, "%s\titer\t0\t%s\t%.3f\t%.4f\n", name.c_str(), cell,
                             s.outliers_pct, s.true_pct);
            }
            std::printf("\n");
          }
        }
      }
    }
  }
  std::printf(
      "best iterated with <= 0.5 %% of the scan removed: %s removes %.1f %% of the "
      "injected points (%.3f %% of the scan)\n",
      iter_best.cell.c_str(), iter_best.s.outliers_pct, iter_best.s.true_pct);
  print_bands(iter_best.s);

  // The single pass K, SIGMA, through find_outliers itself (the rule PCL's filter is checked
  // against).
  OutlierOptions o;
  o.k = default_k;
  o.sigma = default_sigma;
  const OutlierResult r = find_outliers(p, o);
  const Scores single = score_removed([&](std::size_t i) { return r.outlier[i] != 0; });
  std::printf(
      "single pass sor:%zu,%g (find_outliers): removes %.1f %% of the injected points, %.3f %% "
      "of the scan; per band:",
      default_k, default_sigma, single.outliers_pct, single.true_pct);
  band_list(single);

  // A chain of passes "K1,SIGMA1+K2,SIGMA2+...", through find_outliers itself (checked against
  // PCL's filter run on its own output).
  if (argc > 7) {
    std::vector<OutlierOptions> chain;
    for (const char* c = argv[7]; *c;) {
      char* end;
      OutlierOptions pass;
      pass.k = std::strtoull(c, &end, 10);
      pass.sigma = std::strtod(end + 1, &end);
      chain.push_back(pass);
      c = *end == '+' ? end + 1 : end;
    }
    const OutlierPassesResult rc = find_outliers(p, chain);
    const Scores passes = score_removed([&](std::size_t i) { return rc.outlier[i] != 0; });
    std::printf("passes sor:%s (find_outliers, removed", argv[7]);
    for (const OutlierResult& pass : rc.passes) std::printf(" %zu", pass.removed);
    std::printf(
        " per pass): removes %.1f %% of the injected points, %.3f %% of the scan; per band:",
        passes.outliers_pct, passes.true_pct);
    band_list(passes);
  }
  // The same rules on the scan alone (no outliers to inflate the deviation): what they remove of
  // a clean scan.
  {
    const std::span<const Vec3f> clean(p.data(), n_true);
    std::printf("clean scan %s (no injected points): single pass sor:%zu,%g removes %.3f %%",
                name.c_str(), default_k, default_sigma,
                100.0 * double(find_outliers(clean, o).removed) / double(n_true));
    if (argc > 7) {
      std::vector<OutlierOptions> chain;
      for (const char* c = argv[7]; *c;) {
        char* end;
        OutlierOptions pass;
        pass.k = std::strtoull(c, &end, 10);
        pass.sigma = std::strtod(end + 1, &end);
        chain.push_back(pass);
        c = *end == '+' ? end + 1 : end;
      }
      std::printf(", passes sor:%s %.3f %%", argv[7],
                  100.0 * double(find_outliers(clean, chain).removed) / double(n_true));
    }
    std::printf("\n");
  }
  if (cells) std::fclose(cells);
  return 0;
}
