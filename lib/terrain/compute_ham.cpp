#include "terrain/compute_ham.h"

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "splatkit/error.h"
#include "terrain/fill_voids.h"

namespace splatkit::terrain {

namespace {

// One Sobel magnitude row from three source rows (above, centre, below), clamp-to-edge in x.
// Every term is a difference of two neighbouring samples first (exact in float for samples
// within a factor of two of each other, as heights far above zero are), then the weighted sum:
// no cancellation against the heights' own magnitude.
inline float sobel_at(const float* a, const float* c, const float* b, int64_t xl, int64_t x,
                      int64_t xr) {
  const float dx = (b[xl] - a[xl]) + 2.0f * (b[x] - a[x]) + (b[xr] - a[xr]);
  const float dy = (a[xr] - a[xl]) + 2.0f * (c[xr] - c[xl]) + (b[xr] - b[xl]);
  return std::sqrt(dx * dx + dy * dy);
}

void sobel_row(const float* __restrict a, const float* __restrict c, const float* __restrict b,
               int64_t w, float* __restrict out) {
  out[0] = sobel_at(a, c, b, 0, 0, std::min<int64_t>(1, w - 1));
  for (int64_t x = 1; x < w - 1; ++x) {
    const float dx = (b[x - 1] - a[x - 1]) + 2.0f * (b[x] - a[x]) + (b[x + 1] - a[x + 1]);
    const float dy = (a[x + 1] - a[x - 1]) + 2.0f * (c[x + 1] - c[x - 1]) + (b[x + 1] - b[x - 1]);
    out[x] = std::sqrt(dx * dx + dy * dy);
  }
  if (w > 1) out[w - 1] = sobel_at(a, c, b, w - 2, w - 1, w - 1);
}

// out[x] = the largest v[q] over q in [x - r, x + r] ∩ [0, w) with skip[q] == 0 (skip may be
// null), or 0 when there is none (v >= 0): van Herk's running maximum over blocks of 2r + 1
// [vanHerk92], linear in w whatever r.
void window_max(const float* v, const uint8_t* skip, int64_t w, int64_t r, float* out,
                std::vector<float>& prefix, std::vector<float>& suffix) {
  const int64_t k = 2 * r + 1, n = w + 2 * r;
  prefix.resize(std::size_t(n));
  suffix.resize(std::size_t(n));
  auto value = [&](int64_t i) {
    const int64_t x = i - r;
    return x < 0 || x >= w || (skip && skip[x]) ? 0.0f : v[x];
  };
  for (int64_t i = 0; i < n; ++i)
    prefix[std::size_t(i)] = i % k == 0 ? value(i) : std::max(prefix[std::size_t(i - 1)], value(i));
  for (int64_t i = n - 1; i >= 0; --i)
    suffix[std::size_t(i)] =
        i % k == k - 1 || i == n - 1 ? value(i) : std::max(suffix[std::size_t(i + 1)], value(i));
  for (int64_t x = 0; x < w; ++x)
    out[x] = std::max(suffix[std::size_t(x)], prefix[std::size_t(x + 2 * r)]);
}

struct TileAcc {
  float ham = 0, h = -INFINITY;
  uint32_t x = 0, y = 0, voids = 0;
};

// Folds `b` (later rows) into `a`: the larger HAM, the larger height, the first on ties.
void merge(TileAcc& a, const TileAcc& b) {
  a.ham = std::max(a.ham, b.ham);
  if (b.h > a.h) {
    a.h = b.h;
    a.x = b.x;
    a.y = b.y;
  }
  a.voids += b.voids;
}

}  // namespace

HamTiles compute_ham(HeightmapSource& source, const HamOptions& o, HamStats& stats,
                     const HamRowSink& sink, const ProgressFn& progress) {
  if (o.tile < 1 || o.tile > 65536) throw_usage("--tile must be in [1, 65536]");
  const HeightmapInfo& info = source.info();
  const int64_t w = info.width, h = info.height, T = o.tile;
  const bool has_nodata = o.has_nodata || info.has_nodata;
  const auto nodata = float(o.has_nodata ? o.nodata : info.nodata);
  const auto zs = float(o.z_scale);

  // Band: a multiple of the reader's band, about band_bytes of rows.
  const int64_t reader_rows = std::max<int64_t>(1, info.band_rows);
  int64_t band = std::max<int64_t>(8, o.band_bytes / std::max<int64_t>(1, w * 4));
  band = std::max(reader_rows, band / reader_rows * reader_rows);
  band = std::min(band, h);
  const int64_t lookahead = default_lookahead(w);
  // Rows held at once: the band with its halo, the void filler's ring, per-thread rows, the HAM
  // ring with its void flags and bounds.
  const double tiles_bytes = 20.0 * double((w + T - 1) / T) * double((h + T - 1) / T);
  const double held =
      double(w) * (4.0 * double(band + 4) + 5.0 * double(lookahead + 2 * reader_rows + 64) +
                   9.0 * double(band + 2 * kVoidRing + 1)) +
      tiles_bytes;
  if (held > double(int64_t(4) << 30))
    throw_unsupported("the heightmap", std::to_string(w) + " x " + std::to_string(h) +
                                           " texels in tiles of " + std::to_string(T) + " need " +
                                           std::to_string(int64_t(held / double(1 << 20))) +
                                           " MiB in memory at once (limit 4096)");
  HamTiles tiles;
  tiles.resize(w, h, T);
  tiles.z_scale = o.z_scale;
  stats = {};
  stats.band_rows = band;
  stats.samples = uint64_t(w) * uint64_t(h);

  VoidFiller filler(source, has_nodata, nodata, lookahead);

  // The window of filled heights: image rows [lo, loaded), lo = first row a band needs.
  std::vector<float> window;
  int64_t lo = 0, loaded = 0, produced = 0;
  std::vector<uint32_t> row_voids;  // per window row and tile column: voids filled
  float h_min = INFINITY, h_max = -INFINITY;
  bool overflow = false;  // a HAM value that is not finite
  // Rows with replaced samples: the replaced flags dilated by 2 texels along the row.
  std::map<int64_t, std::vector<uint8_t>> replaced_rows;

  // Rows are filled into `ahead` (by a task while the previous band is computed), then moved
  // to the window.
  std::vector<float> ahead;
  std::vector<uint32_t> ahead_voids;
  std::vector<std::pair<int64_t, std::vector<uint8_t>>> ahead_replaced;
  int64_t ahead_rows = 0;
  auto produce = [&](int64_t n) {
    ahead.resize(std::size_t(n * w));
    ahead_voids.assign(std::size_t(n * tiles.tiles_x), 0u);
    for (int64_t r = 0; r < n; ++r) {
      float* row = ahead.data() + std::size_t(r * w);
      uint32_t* rv = ahead_voids.data() + std::size_t(r * tiles.tiles_x);
      const int64_t v = filler.next(row);
      if (v > 0) {
        const std::vector<uint8_t>& mask = filler.mask();
        for (int64_t x = 0; x < w; ++x) rv[x / T] += mask[std::size_t(x)];
        stats.voids += uint64_t(v);
        stats.void_rows += v == w;
      }
      if (filler.any_replaced()) {
        const std::vector<uint8_t>& rep = filler.replaced();
        std::vector<uint8_t> dilated(std::size_t(w), 0);
        bool any = false;
        for (int64_t x = 0; x < w; ++x)
          if (rep[std::size_t(x)]) {
            any = true;
            for (int64_t xx = std::max<int64_t>(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx)
              dilated[std::size_t(xx)] = 1;
          }
        if (any) ahead_replaced.emplace_back(produced, std::move(dilated));
      }
      ++produced;
      if (zs != 1.0f)
        for (int64_t x = 0; x < w; ++x) row[x] *= zs;
    }
    ahead_rows = n;
  };
  auto take_ahead = [&] {
    window.insert(window.end(), ahead.begin(), ahead.begin() + ahead_rows * w);
    row_voids.insert(row_voids.end(), ahead_voids.begin(),
                     ahead_voids.begin() + ahead_rows * tiles.tiles_x);
    for (auto& [y, flags] : ahead_replaced) replaced_rows.emplace(y, std::move(flags));
    ahead_replaced.clear();
    loaded += ahead_rows;
    ahead_rows = 0;
  };

  // HAM rows go to a ring (row r in slot r % cap) and leave it kVoidRing rows later, once the
  // bound of their texels that depend on filled samples ("affected") is known.
  const int64_t ring_r = kVoidRing, cap = band + 2 * ring_r + 1;
  std::vector<float> ham_ring(std::size_t(cap * w));
  std::vector<uint8_t> has_affected(std::size_t(cap), 0), bound_ready(std::size_t(cap), 0);
  std::vector<uint8_t> affected;  // cap × w flags, allocated at the first void
  std::vector<float> row_bound;   // cap × w: window_max of each row's unaffected HAM (lazily)
  auto slot = [&](int64_t r) { return std::size_t(r % cap); };
  auto ham_row = [&](int64_t r) { return ham_ring.data() + slot(r) * std::size_t(w); };
  // Bounds the affected texels of rows [f0, f1), adds them to the tiles, hands the rows on.
  auto finish_rows = [&](int64_t f0, int64_t f1) {
    std::vector<int64_t> rows, need;
    for (int64_t r = f0; r < f1; ++r)
      if (has_affected[slot(r)]) rows.push_back(r);
    if (!rows.empty()) {
      if (row_bound.empty()) row_bound.resize(std::size_t(cap * w));
      for (int64_t r : rows)
        for (int64_t y = std::max<int64_t>(0, r - ring_r); y <= std::min(h - 1, r + ring_r); ++y)
          if (!bound_ready[slot(y)]) {
            bound_ready[slot(y)] = 1;
            need.push_back(y);
          }
      tbb::parallel_for(std::size_t(0), need.size(), [&](std::size_t i) {
        std::vector<float> prefix, suffix;
        const int64_t y = need[i];
        window_max(ham_row(y), has_affected[slot(y)] ? affected.data() + slot(y) * w : nullptr, w,
                   ring_r, row_bound.data() + slot(y) * w, prefix, suffix);
      });
      tbb::parallel_for(std::size_t(0), rows.size(), [&](std::size_t i) {
        const int64_t r = rows[i];
        std::vector<float> bound(row_bound.data() + slot(r) * w,
                                 row_bound.data() + (slot(r) + 1) * w);
        for (int64_t y = std::max<int64_t>(0, r - ring_r); y <= std::min(h - 1, r + ring_r); ++y) {
          const float* b = row_bound.data() + slot(y) * w;
          for (int64_t x = 0; x < w; ++x)
            bound[std::size_t(x)] = std::max(bound[std::size_t(x)], b[x]);
        }
        float* hr = ham_row(r);
        const uint8_t* a = affected.data() + slot(r) * w;
        for (int64_t x = 0; x < w; ++x)
          if (a[x]) hr[x] = std::min(hr[x], bound[std::size_t(x)]);
      });
      for (int64_t r : rows) {  // the bounded texels into their tiles
        const float* hr = ham_row(r);
        const uint8_t* a = affected.data() + slot(r) * w;
        float* tile_row = tiles.ham_max.data() + std::size_t((r / T) * tiles.tiles_x);
        for (int64_t x = 0; x < w; ++x)
          if (a[x]) {
            tile_row[x / T] = std::max(tile_row[x / T], hr[x]);
            stats.ham_max = std::max(stats.ham_max, double(hr[x]));
          }
      }
    }
    if (sink)  // in runs of rows contiguous in the ring
      for (int64_t r = f0; r < f1;) {
        const int64_t n = std::min(f1 - r, cap - int64_t(slot(r)));
        sink(n, ham_row(r));
        r += n;
      }
  };

  int64_t finished = 0;  // rows handed on
  for (int64_t b0 = 0; b0 < h; b0 += band) {
    const int64_t b1 = std::min(h, b0 + band);
    const int64_t need_lo = std::max<int64_t>(0, b0 - 2), need_hi = std::min(h, b1 + 2);
    if (need_lo > lo) {  // drop rows no longer needed
      const int64_t drop = need_lo - lo;
      window.erase(window.begin(), window.begin() + drop * w);
      row_voids.erase(row_voids.begin(), row_voids.begin() + drop * tiles.tiles_x);
      replaced_rows.erase(replaced_rows.begin(), replaced_rows.lower_bound(need_lo));
      lo = need_lo;
    }
    if (loaded < need_hi) {  // the first band (later ones were read ahead)
      produce(need_hi - loaded);
      take_ahead();
    }
    // Read the next band's rows while this one is computed.
    const int64_t next_hi = std::min(h, b1 + band + 2);
    tbb::task_group prefetch;
    if (next_hi > loaded) prefetch.run([&, n = next_hi - loaded] { produce(n); });
    auto hrow = [&](int64_t r) {
      r = std::clamp<int64_t>(r, 0, h - 1);
      return window.data() + (r - lo) * w;
    };
    // Replaced samples within 2 rows of the band: flag its affected texels.
    const bool band_voids = replaced_rows.lower_bound(b0 - 2) != replaced_rows.end() &&
                            replaced_rows.lower_bound(b0 - 2)->first <= b1 + 1;
    if (band_voids && affected.empty()) affected.resize(std::size_t(cap * w));

    // Runs of rows, one task each; per-run tile records merged in row order afterwards.
    const int64_t run = std::max<int64_t>(8, (b1 - b0 + 7) / 8);
    const int64_t runs = (b1 - b0 + run - 1) / run;
    std::vector<std::vector<TileAcc>> parts(static_cast<std::size_t>(runs));
    std::vector<double> run_ham_max(static_cast<std::size_t>(runs), 0.0);
    std::vector<std::pair<float, float>> run_h(static_cast<std::size_t>(runs));
    std::vector<uint8_t> run_overflow(static_cast<std::size_t>(runs), 0);
    try {
      tbb::parallel_for(int64_t(0), runs, [&](int64_t k) {
        const int64_t r0 = b0 + k * run, r1 = std::min(b1, r0 + run);
        const int64_t ty0 = r0 / T, ty1 = (r1 - 1) / T;
        std::vector<TileAcc>& acc = parts[std::size_t(k)];
        acc.assign(std::size_t((ty1 - ty0 + 1) * tiles.tiles_x), TileAcc{});
        std::vector<float> ring(
            static_cast<std::size_t>(3 * w));  // M rows r-1, r, r+1 in slots (row+3)%3
        auto mrow = [&](int64_t r) { return ring.data() + ((r + 3) % 3) * w; };
        auto compute_m = [&](int64_t r) {  // M of row r (clamped to the map)
          const int64_t rc = std::clamp<int64_t>(r, 0, h - 1);
          sobel_row(hrow(rc - 1), hrow(rc), hrow(rc + 1), w, mrow(r));
        };
        compute_m(r0 - 1);
        compute_m(r0);
        float ham_max = 0, lo_h = INFINITY, hi_h = -INFINITY;
        for (int64_t r = r0; r < r1; ++r) {
          compute_m(r + 1);
          const float* above = r == 0 ? mrow(r) : mrow(r - 1);
          const float* below = r == h - 1 ? mrow(r) : mrow(r + 1);
          float* out = ham_row(r);
          sobel_row(above, mrow(r), below, w, out);
          // Heights so large that their slopes overflow give inf or NaN here (which the maxima
          // below would skip).
          bool finite = true;
          for (int64_t x = 0; x < w; ++x) finite &= out[x] <= std::numeric_limits<float>::max();
          run_overflow[std::size_t(k)] |= !finite;
          bound_ready[slot(r)] = 0;
          uint8_t* aff = nullptr;  // this row's affected texels, or null
          if (band_voids)
            for (int64_t y = std::max<int64_t>(0, r - 2); y <= std::min(h - 1, r + 2); ++y) {
              const auto it = replaced_rows.find(y);
              if (it == replaced_rows.end()) continue;
              if (!aff) {
                aff = affected.data() + slot(r) * w;
                std::fill(aff, aff + w, uint8_t(0));
              }
              for (int64_t x = 0; x < w; ++x) aff[x] |= it->second[std::size_t(x)];
            }
          has_affected[slot(r)] = aff != nullptr;
          const float* hr = hrow(r);
          for (int64_t x = 0; x < w; ++x) {
            lo_h = std::min(lo_h, hr[x]);
            hi_h = std::max(hi_h, hr[x]);
          }
          const uint32_t* rv = row_voids.data() + (r - lo) * tiles.tiles_x;
          TileAcc* a = acc.data() + (r / T - ty0) * tiles.tiles_x;
          for (int64_t tx = 0; tx < tiles.tiles_x; ++tx) {
            const int64_t x0 = tx * T, x1 = std::min(w, x0 + T);
            float hm = 0;  // affected texels join their tile once bounded (finish_rows)
            int64_t best = x0;
            float hh = hr[x0];
            if (aff) {
              for (int64_t x = x0; x < x1; ++x) {
                if (!aff[x]) hm = std::max(hm, out[x]);
                if (hr[x] > hh) {
                  hh = hr[x];
                  best = x;
                }
              }
            } else {
              for (int64_t x = x0; x < x1; ++x) {
                hm = std::max(hm, out[x]);
                if (hr[x] > hh) {
                  hh = hr[x];
                  best = x;
                }
              }
            }
            TileAcc& t = a[tx];
            t.ham = std::max(t.ham, hm);
            if (hh > t.h) {
              t.h = hh;
              t.x = uint32_t(best);
              t.y = uint32_t(r);
            }
            t.voids += rv[tx];
            ham_max = std::max(ham_max, hm);
          }
        }
        run_ham_max[std::size_t(k)] = ham_max;
        run_h[std::size_t(k)] = {lo_h, hi_h};
      });
      for (const uint8_t flag : run_overflow) overflow |= flag != 0;
    } catch (...) {
      try {
        prefetch.wait();
      } catch (...) {
      }
      throw;
    }
    prefetch.wait();
    for (int64_t k = 0; k < runs; ++k) {
      const int64_t r0 = b0 + k * run;
      const int64_t ty0 = r0 / T;
      const std::vector<TileAcc>& acc = parts[std::size_t(k)];
      for (std::size_t i = 0; i < acc.size(); ++i) {
        const std::size_t t = std::size_t(ty0 * tiles.tiles_x) + i;
        TileAcc cur{tiles.ham_max[t], tiles.h_max[t], tiles.x[t], tiles.y[t], tiles.voids[t]};
        merge(cur, acc[i]);
        tiles.ham_max[t] = cur.ham;
        tiles.h_max[t] = cur.h;
        tiles.x[t] = cur.x;
        tiles.y[t] = cur.y;
        tiles.voids[t] = cur.voids;
      }
      stats.ham_max = std::max(stats.ham_max, run_ham_max[std::size_t(k)]);
      h_min = std::min(h_min, run_h[std::size_t(k)].first);
      h_max = std::max(h_max, run_h[std::size_t(k)].second);
    }
    // Rows whose ring of kVoidRing rows below is computed are final.
    const int64_t final_rows = b1 == h ? h : std::max(finished, b1 - ring_r);
    finish_rows(finished, final_rows);
    finished = final_rows;
    if (ahead_rows > 0) take_ahead();
    progress(double(b1) / double(h), "ham");
  }
  if (stats.voids == stats.samples)
    throw Error(ErrorKind::kBadInput,
                "every sample is a void (no data): there is no height to fill them from");
  if (overflow || !std::isfinite(h_min) || !std::isfinite(h_max)) {
    // The option's fault when it scales; else the heights' own (near the float range).
    std::ostringstream what;
    if (o.z_scale != 1) {
      what << "--z-scale " << o.z_scale
           << " makes the heights or their slopes too large for float arithmetic";
      throw_usage(what.str());
    }
    what << "heights up to " << std::max(std::fabs(h_min), std::fabs(h_max))
         << ": their slopes are too large for float arithmetic";
    throw Error(ErrorKind::kBadInput, what.str());
  }
  stats.h_min = double(h_min);
  stats.h_max = double(h_max);
  tiles.header["h_min"] = stats.h_min;
  tiles.header["h_max"] = stats.h_max;
  tiles.header["ham_max"] = stats.ham_max;
  tiles.header["voids"] = stats.voids;
  return tiles;
}

}  // namespace splatkit::terrain
