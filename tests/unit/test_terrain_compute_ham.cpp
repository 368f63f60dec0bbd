// compute_ham against a plain reference written for the test (whole map in memory, unfused, in
// double): every HAM texel within 1e-5 of the reference (relative to the map's largest HAM), the
// tile records exact, on real SRTM tiles with voids and on synthetic maps (noise, hills far above
// zero, flat), for bands of every size and 1 or 2 threads. Filled voids must not raise the HAM
// above the range of the void-free terrain around them.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "terrain/compute_ham.h"
#include "terrain/fill_voids.h"
#include "terrain/terrain_images.h"
#include "test_terrain_support.h"

namespace splatkit::terrain {
namespace {

using test::MemorySource;

// The reference: Sobel magnitude twice with clamp-to-edge, in double.
std::vector<double> sobel_ref(const std::vector<double>& a, int64_t w, int64_t h) {
  std::vector<double> out(a.size());
  auto at = [&](int64_t x, int64_t y) {
    x = std::clamp<int64_t>(x, 0, w - 1);
    y = std::clamp<int64_t>(y, 0, h - 1);
    return a[std::size_t(y * w + x)];
  };
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x) {
      const double dx = (at(x - 1, y + 1) + 2 * at(x, y + 1) + at(x + 1, y + 1)) -
                        (at(x - 1, y - 1) + 2 * at(x, y - 1) + at(x + 1, y - 1));
      const double dy = (at(x + 1, y - 1) + 2 * at(x + 1, y) + at(x + 1, y + 1)) -
                        (at(x - 1, y - 1) + 2 * at(x - 1, y) + at(x - 1, y + 1));
      out[std::size_t(y * w + x)] = std::sqrt(dx * dx + dy * dy);
    }
  return out;
}

struct Reference {
  std::vector<double> ham, raw;  // raw: before the bound over voids
  std::vector<double> ham_max, h_max;
  std::vector<uint32_t> x, y;
};

// The texels whose HAM depends on a replaced sample: within 2 texels (Chebyshev) of one.
std::vector<uint8_t> affected_texels(const std::vector<uint8_t>& replaced, int64_t w, int64_t h) {
  std::vector<uint8_t> a(std::size_t(w * h), 0);
  if (replaced.empty()) return a;
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x)
      if (replaced[std::size_t(y * w + x)])
        for (int64_t yy = std::max<int64_t>(0, y - 2); yy <= std::min(h - 1, y + 2); ++yy)
          for (int64_t xx = std::max<int64_t>(0, x - 2); xx <= std::min(w - 1, x + 2); ++xx)
            a[std::size_t(yy * w + xx)] = 1;
  return a;
}

// "The surrounding terrain" of texel (x, y): the texels within kVoidRing of it (Chebyshev) that
// are not affected. Returns, for every affected texel, the largest of `ham` over them, or -1 when
// there is none (other texels: -1): the maximum over the rows of the window of the maximum along
// each row.
template <class T>
std::vector<double> surrounding_max(const std::vector<T>& ham, const std::vector<uint8_t>& affected,
                                    int64_t w, int64_t h) {
  std::vector<double> along(ham.size(), -1), out(ham.size(), -1);
  std::vector<uint8_t> row_needed(std::size_t(h), 0);  // rows within kVoidRing of an affected one
  for (int64_t y = 0; y < h; ++y)
    if (std::find(affected.begin() + y * w, affected.begin() + (y + 1) * w, 1) !=
        affected.begin() + (y + 1) * w)
      for (int64_t yy = std::max<int64_t>(0, y - kVoidRing); yy <= std::min(h - 1, y + kVoidRing);
           ++yy)
        row_needed[std::size_t(yy)] = 1;
  for (int64_t y = 0; y < h; ++y)
    if (row_needed[std::size_t(y)])
      for (int64_t x = 0; x < w; ++x)
        for (int64_t xx = std::max<int64_t>(0, x - kVoidRing); xx <= std::min(w - 1, x + kVoidRing);
             ++xx)
          if (!affected[std::size_t(y * w + xx)])
            along[std::size_t(y * w + x)] =
                std::max(along[std::size_t(y * w + x)], double(ham[std::size_t(y * w + xx)]));
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x)
      if (affected[std::size_t(y * w + x)])
        for (int64_t yy = std::max<int64_t>(0, y - kVoidRing); yy <= std::min(h - 1, y + kVoidRing);
             ++yy)
          out[std::size_t(y * w + x)] =
              std::max(out[std::size_t(y * w + x)], along[std::size_t(yy * w + x)]);
  return out;
}

// `filled`: the heights after void filling (fill_row_voids is tested on its own below);
// `replaced`: the samples the filler replaced (empty: none). The rule of formats/ham.md, plainly:
// the HAM of an affected texel is at most the largest HAM of its surrounding terrain, 0 without.
Reference reference(const std::vector<float>& filled, int64_t w, int64_t h, int64_t T,
                    const std::vector<uint8_t>& replaced = {}) {
  std::vector<double> hd(filled.begin(), filled.end());
  Reference r;
  r.raw = sobel_ref(sobel_ref(hd, w, h), w, h);
  const std::vector<double>& raw = r.raw;
  r.ham = raw;
  const std::vector<uint8_t> affected = affected_texels(replaced, w, h);
  if (!replaced.empty()) {
    const std::vector<double> around = surrounding_max(raw, affected, w, h);
    for (std::size_t i = 0; i < raw.size(); ++i)
      if (affected[i]) r.ham[i] = std::min(raw[i], std::max(0.0, around[i]));
  }
  const int64_t tx = (w + T - 1) / T, ty = (h + T - 1) / T;
  r.ham_max.assign(std::size_t(tx * ty), 0);
  r.h_max.assign(std::size_t(tx * ty), -INFINITY);
  r.x.assign(std::size_t(tx * ty), 0);
  r.y.assign(std::size_t(tx * ty), 0);
  for (int64_t yy = 0; yy < h; ++yy)
    for (int64_t xx = 0; xx < w; ++xx) {
      const std::size_t t = std::size_t((yy / T) * tx + xx / T), i = std::size_t(yy * w + xx);
      r.ham_max[t] = std::max(r.ham_max[t], r.ham[i]);
      if (hd[i] > r.h_max[t]) {
        r.h_max[t] = hd[i];
        r.x[t] = uint32_t(xx);
        r.y[t] = uint32_t(yy);
      }
    }
  return r;
}

struct Filled {
  std::vector<float> heights;
  std::vector<uint8_t> replaced;  // 1 = replaced by the filler (a void or a void edge)
};

Filled filled_copy(const std::vector<float>& v, int64_t w, int64_t h, bool nd, float nodata) {
  MemorySource src(v, w, h);
  if (nd) src.set_nodata(nodata);
  VoidFiller filler(src, nd, nodata, default_lookahead(w));
  Filled out;
  out.heights.resize(v.size());
  out.replaced.assign(v.size(), 0);
  for (int64_t y = 0; y < h; ++y) {
    filler.next(out.heights.data() + y * w);
    if (filler.any_replaced())
      std::copy(filler.replaced().begin(), filler.replaced().end(), out.replaced.begin() + y * w);
  }
  return out;
}

struct HamRun {
  HamTiles tiles;
  HamStats stats;
  std::vector<float> ham;
};

HamRun run_ham(const std::vector<float>& data, int64_t w, int64_t h, HamOptions o,
               int64_t band_rows = 64, bool nodata = false, float nodata_value = 0) {
  MemorySource src(data, w, h, band_rows);
  if (nodata) src.set_nodata(nodata_value);
  HamRun r;
  r.tiles = compute_ham(src, o, r.stats, [&](int64_t rows, const float* p) {
    r.ham.insert(r.ham.end(), p, p + rows * w);
  });
  return r;
}

void expect_matches(const HamRun& got, const Reference& ref, const std::string& what) {
  const double scale = std::max(1e-30, *std::max_element(ref.ham.begin(), ref.ham.end()));
  ASSERT_EQ(got.ham.size(), ref.ham.size()) << what;
  double worst = 0;
  for (std::size_t i = 0; i < ref.ham.size(); ++i)
    worst = std::max(worst, std::abs(double(got.ham[i]) - ref.ham[i]) / scale);
  EXPECT_LE(worst, 1e-5) << what;
  ASSERT_EQ(got.tiles.size(), ref.ham_max.size()) << what;
  for (std::size_t t = 0; t < ref.ham_max.size(); ++t) {
    EXPECT_LE(std::abs(double(got.tiles.ham_max[t]) - ref.ham_max[t]) / scale, 1e-5) << what;
    EXPECT_EQ(double(got.tiles.h_max[t]), ref.h_max[t]) << what << " tile " << t;
    EXPECT_EQ(got.tiles.x[t], ref.x[t]) << what << " tile " << t;
    EXPECT_EQ(got.tiles.y[t], ref.y[t]) << what << " tile " << t;
  }
  // Tile records exact against our own full-resolution rows.
  const HamTiles& t = got.tiles;
  std::vector<float> own(t.size(), 0.0f);
  for (int64_t y = 0; y < t.height; ++y)
    for (int64_t x = 0; x < t.width; ++x) {
      float& m = own[std::size_t((y / t.tile) * t.tiles_x + x / t.tile)];
      m = std::max(m, got.ham[std::size_t(y * t.width + x)]);
    }
  EXPECT_EQ(own, t.ham_max) << what;
}

std::vector<float> noisy_hills(int64_t w, int64_t h, uint32_t seed, double base) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  std::vector<float> v(std::size_t(w * h));
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x)
      v[std::size_t(y * w + x)] =
          float(base + 800 * std::sin(double(x) * 0.05) * std::cos(double(y) * 0.031) +
                300 *
                    std::exp(-(std::pow(double(x) - 40, 2) + std::pow(double(y) - 30, 2)) / 200)) +
          noise(rng);
  return v;
}

TEST(TerrainComputeHam, MatchesTheReferenceOnSyntheticMapsForEveryBandAndThreadCount) {
  const int64_t w = 157, h = 101;
  const std::vector<float> v = noisy_hills(w, h, 7, 8000.0);
  for (int64_t T : {1, 16, 64, 200}) {
    const Reference ref = reference(v, w, h, T);
    for (int64_t band_bytes : {int64_t(1), int64_t(w * 4 * 13), int64_t(1) << 30})
      for (int64_t reader_rows : {1, 7, 64})
        for (int threads : {1, 2}) {
          tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
          HamOptions o;
          o.tile = T;
          o.band_bytes = band_bytes;
          expect_matches(run_ham(v, w, h, o, reader_rows), ref,
                         "T=" + std::to_string(T) + " band=" + std::to_string(band_bytes) +
                             " reader=" + std::to_string(reader_rows));
        }
  }
}

TEST(TerrainComputeHam, ThinMapsAndSingleTexels) {
  for (auto [w, h] : {std::pair<int64_t, int64_t>{1, 1}, {1, 9}, {9, 1}, {2, 2}, {3, 50}}) {
    const std::vector<float> v = noisy_hills(w, h, 3, 100.0);
    expect_matches(run_ham(v, w, h, HamOptions{}), reference(v, w, h, 64),
                   std::to_string(w) + "x" + std::to_string(h));
  }
}

TEST(TerrainComputeHam, FlatTerrainHasZeroHamAndTheFirstTexelOfEachTile) {
  const int64_t w = 100, h = 70;
  const std::vector<float> v(std::size_t(w * h), 1234.5f);
  HamOptions o;
  o.tile = 32;
  const HamRun r = run_ham(v, w, h, o);
  for (float x : r.ham) EXPECT_EQ(x, 0.0f);
  for (std::size_t t = 0; t < r.tiles.size(); ++t) {
    EXPECT_EQ(r.tiles.ham_max[t], 0.0f);
    EXPECT_EQ(r.tiles.h_max[t], 1234.5f);
    EXPECT_EQ(r.tiles.x[t], uint32_t(int64_t(t) % r.tiles.tiles_x * 32));
    EXPECT_EQ(r.tiles.y[t], uint32_t(int64_t(t) / r.tiles.tiles_x * 32));
  }
}

TEST(TerrainComputeHam, ZScaleScalesHeightsAndHam) {
  const int64_t w = 40, h = 30;
  const std::vector<float> v = noisy_hills(w, h, 5, 10.0);
  HamOptions o;
  o.z_scale = 4;
  const HamRun a = run_ham(v, w, h, HamOptions{}), b = run_ham(v, w, h, o);
  for (std::size_t t = 0; t < a.tiles.size(); ++t) {
    EXPECT_FLOAT_EQ(b.tiles.h_max[t], 4 * a.tiles.h_max[t]);
    EXPECT_NEAR(b.tiles.ham_max[t], 4 * a.tiles.ham_max[t], 1e-4 * b.stats.ham_max);
  }
}

TEST(TerrainComputeHam, AllVoidRowsAreFilledFromAboveAndBelow) {
  const int64_t w = 20, h = 12;
  std::vector<float> v = noisy_hills(w, h, 9, 50.0);
  for (int64_t y : {0, 1, 6, 11}) std::fill(v.begin() + y * w, v.begin() + (y + 1) * w, NAN);
  const HamRun r = run_ham(v, w, h, HamOptions{});
  EXPECT_EQ(r.stats.voids, uint64_t(4 * w));
  EXPECT_EQ(r.stats.void_rows, 4u);
  const Filled filled = filled_copy(v, w, h, false, 0);
  const std::vector<float>& f = filled.heights;
  expect_matches(r, reference(f, w, h, 64, filled.replaced), "void rows");
  // Filled rows stay within the heights of the rows around them.
  for (int64_t y : {0, 1, 6, 11})
    for (int64_t x = 0; x < w; ++x) {
      const float value = f[std::size_t(y * w + x)];
      EXPECT_GE(value, *std::min_element(v.begin() + 2 * w, v.begin() + 11 * w)) << y;
      EXPECT_LE(value, *std::max_element(v.begin() + 2 * w, v.begin() + 11 * w)) << y;
    }
  EXPECT_EQ(r.tiles.voids[0], uint32_t(4 * w));
}

// A map that is mostly void (an island in a no-data sea, as coastal DEMs and clipped rasters
// are): samples whose row and column hold no valid height still take heights from the island,
// never 0 (which made 0 -> 500 m cliffs around it). Also a single valid sample.
TEST(TerrainFillVoids, AnIslandInAVoidSeaFillsWithinItsHeights) {
  const int64_t w = 200, h = 200;
  std::vector<float> v(std::size_t(w * h), -32768.0f);
  float lo = 1e30f, hi = -1e30f;
  for (int64_t y = 85; y < 115; ++y)
    for (int64_t x = 85; x < 115; ++x) {
      const float z =
          500.0f +
          100.0f * float(std::exp(-double((x - 100) * (x - 100) + (y - 100) * (y - 100)) / 200.0));
      v[std::size_t(y * w + x)] = z;
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  const Filled filled = filled_copy(v, w, h, true, -32768);
  const auto [mn, mx] = std::minmax_element(filled.heights.begin(), filled.heights.end());
  EXPECT_GE(*mn, lo);
  EXPECT_LE(*mx, hi);
  std::vector<float> one(100, -32768.0f);
  one[55] = 3.0f;
  for (float z : filled_copy(one, 10, 10, true, -32768).heights) EXPECT_EQ(z, 3.0f);
}

// A void takes its 8 neighbours with it (void edges carry outliers), and no more: the valid
// heights around it stay (a wider ring took 14 % of a mountain tile's valid samples, and its
// summit).
TEST(TerrainFillVoids, OnlyAVoidsNeighboursAreReplaced) {
  const int64_t w = 30, h = 30;
  std::vector<float> v = noisy_hills(w, h, 5, 40.0);
  v[std::size_t(15 * w + 15)] = -32768.0f;
  const Filled filled = filled_copy(v, w, h, true, -32768);
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y * w + x);
      const bool ring = std::abs(x - 15) <= 1 && std::abs(y - 15) <= 1;
      EXPECT_EQ(filled.replaced[i] != 0, ring) << x << "," << y;
      if (!ring) {
        EXPECT_EQ(filled.heights[i], v[i]) << x << "," << y;
      }
    }
}

TEST(TerrainFillVoids, RunsBecomeLinesBetweenTheirNeighbours) {
  std::vector<float> row = {-32768, 10, -32768, -32768, -32768, 20, NAN, -32768};
  EXPECT_EQ(fill_row_voids(row.data(), int64_t(row.size()), true, -32768), 6);
  EXPECT_EQ(row, (std::vector<float>{10, 10, 12.5f, 15, 17.5f, 20, 20, 20}));
  std::vector<float> none = {NAN, NAN};
  EXPECT_EQ(fill_row_voids(none.data(), 2, false, 0), 2);
}

// The criterion "voids produce no HAM spike above the surrounding terrain's maximum", on the
// library's own output: every affected texel (within 2 texels of a replaced sample) has a HAM at
// most the largest HAM of its surrounding terrain (the unaffected texels within kVoidRing), and 0
// when it has none. Also per tile: the affected texels of a tile against the unaffected texels of
// that tile and the 8 around it (a looser, tile-sized "surrounding").
struct SpikeCheck {
  std::size_t affected = 0, over = 0;      // affected texels, those above their surrounding maximum
  double worst_texel = 0, worst_tile = 0;  // largest ratio affected HAM / surrounding maximum
};

// `around`: surrounding_max of r.ham, or empty to compute it here (it reads unaffected texels
// only, so the bounded and the unbounded HAM share it).
SpikeCheck check_spikes(const HamRun& r, const std::vector<uint8_t>& replaced, int64_t w, int64_t h,
                        int64_t T, std::vector<double> around = {}) {
  SpikeCheck c;
  const std::vector<uint8_t> affected = affected_texels(replaced, w, h);
  if (around.empty()) around = surrounding_max(r.ham, affected, w, h);
  const int64_t tx = (w + T - 1) / T, ty = (h + T - 1) / T;
  std::vector<float> clean(std::size_t(tx * ty), 0.0f), dirty(std::size_t(tx * ty), -1.0f);
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y * w + x), k = std::size_t((y / T) * tx + x / T);
      const float v = r.ham[i];
      if (!affected[i]) {
        clean[k] = std::max(clean[k], v);
        continue;
      }
      dirty[k] = std::max(dirty[k], v);
      ++c.affected;
      const double m = around[i];
      if (double(v) > std::max(0.0, m)) ++c.over;
      if (m > 0) c.worst_texel = std::max(c.worst_texel, double(v) / m);
    }
  for (int64_t j = 0; j < ty; ++j)
    for (int64_t i = 0; i < tx; ++i) {
      const float d = dirty[std::size_t(j * tx + i)];
      if (d <= 0) continue;
      float clean_around = 0;
      for (int64_t y = std::max<int64_t>(0, j - 1); y <= std::min(ty - 1, j + 1); ++y)
        for (int64_t x = std::max<int64_t>(0, i - 1); x <= std::min(tx - 1, i + 1); ++x)
          clean_around = std::max(clean_around, clean[std::size_t(y * tx + x)]);
      c.worst_tile =
          std::max(c.worst_tile, clean_around > 0 ? double(d) / double(clean_around) : INFINITY);
    }
  return c;
}

// Synthetic voids: a large void (wider than twice kVoidRing) holding an island of data and a
// speck of data, voids on the left and bottom borders and in a corner, single-texel voids, a
// column void; the bounded HAM matches the reference for every band and thread count, and no
// affected texel exceeds its surrounding terrain.
TEST(TerrainComputeHam, SyntheticVoidsStayBelowTheirSurroundingTerrain) {
  const int64_t w = 300, h = 220;
  std::vector<float> v = noisy_hills(w, h, 11, 2000.0);
  auto hole = [&](int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y)
      for (int64_t x = x0; x < x1; ++x) v[std::size_t(y * w + x)] = -32768;
  };
  hole(100, 40, 230, 170);            // large void: 130 x 130
  for (int64_t y = 90; y < 112; ++y)  // an island of data inside it, and a 2 x 2 speck
    for (int64_t x = 150; x < 172; ++x) v[std::size_t(y * w + x)] = 2500.0f + float(x - y);
  v[std::size_t(60 * w + 200)] = v[std::size_t(60 * w + 201)] = 2100.0f;
  v[std::size_t(61 * w + 200)] = v[std::size_t(61 * w + 201)] = 2100.0f;
  hole(0, 10, 9, 60);      // left border
  hole(30, h - 6, 80, h);  // bottom border
  hole(w - 12, 0, w, 15);  // top-right corner
  hole(260, 0, 261, h);    // a column void, top to bottom
  for (int64_t k = 0; k < 40; ++k) v[std::size_t(((k * 37) % h) * w + (k * 53) % 90)] = NAN;
  const Filled filled = filled_copy(v, w, h, true, -32768);
  const Reference ref = reference(filled.heights, w, h, 64, filled.replaced);
  for (int64_t band_bytes : {int64_t(1), int64_t(w * 4 * 13), int64_t(1) << 30})
    for (int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      HamOptions o;
      o.band_bytes = band_bytes;
      const HamRun r = run_ham(v, w, h, o, 7, true, -32768);
      const std::string what =
          "band=" + std::to_string(band_bytes) + " threads=" + std::to_string(threads);
      expect_matches(r, ref, what);
      const SpikeCheck c = check_spikes(r, filled.replaced, w, h, 64);
      EXPECT_GT(c.affected, 20000u) << what;
      EXPECT_EQ(c.over, 0u) << what;
      EXPECT_LE(c.worst_texel, 1.0) << what;
      EXPECT_LE(c.worst_tile, 1.0) << what;
    }
  // The bound is not vacuous: unbounded (the reference without it), the filled voids exceed it.
  HamRun unbounded;
  unbounded.ham.assign(ref.raw.begin(), ref.raw.end());
  EXPECT_GT(check_spikes(unbounded, filled.replaced, w, h, 64).over, 0u);
}

// Real SRTM: the library's reader and the reference agree, and no filled void raises the HAM
// above its surrounding terrain (unfilled, the voids give HAM near 7e5).
TEST(TerrainComputeHam, RealSrtmWithVoids) {
  for (const char* path :
       {"/work/shared/data/dem/mt_fuji_90m.tif", "/work/shared/data/dem/mt_rainier_90m.tif",
        "/work/shared/data/dem/mt_everest_90m.tif",
        SPLATKIT_SOURCE_DIR "/data-samples/rainier-srtm.tif"}) {
    if (FILE* f = std::fopen(path, "rb"))
      std::fclose(f);
    else {
      std::printf("%s not present: skipped\n", path);
      continue;
    }
    auto src = open_image_heightmap(path);
    const int64_t w = src->info().width, h = src->info().height;
    ASSERT_TRUE(src->info().has_nodata);
    const float nodata = float(src->info().nodata);
    std::vector<float> raw(std::size_t(w * h));
    src->read_rows(h, raw.data());
    const HamRun r = run_ham(raw, w, h, HamOptions{}, 256, true, nodata);
    const Filled filled = filled_copy(raw, w, h, true, nodata);
    const Reference ref = reference(filled.heights, w, h, 64, filled.replaced);
    expect_matches(r, ref, path);
    const std::vector<double> around =
        surrounding_max(r.ham, affected_texels(filled.replaced, w, h), w, h);
    const SpikeCheck c = check_spikes(r, filled.replaced, w, h, 64, around);
    EXPECT_GT(c.affected, 0u) << path;
    EXPECT_EQ(c.over, 0u) << path;
    EXPECT_LE(c.worst_texel, 1.0) << path;
    EXPECT_LE(c.worst_tile, 1.0) << path;
    // Without the bound (the fill alone) the same voids exceed their surroundings: measured
    // 1.2 to 1.8 times per tile on these maps.
    HamRun unbounded;
    unbounded.ham.assign(ref.raw.begin(), ref.raw.end());
    const SpikeCheck u = check_spikes(unbounded, filled.replaced, w, h, 64, around);
    std::printf(
        "%s: %zu affected texels; bounded: worst texel %.3f, worst tile %.3f of the "
        "surrounding maximum; fill alone: %zu texels above it, worst tile %.3f\n",
        path, c.affected, c.worst_texel, c.worst_tile, u.over, u.worst_tile);
    // Unfilled, the same voids would be cliffs: the checks above can fail.
    const HamRun cliffs = run_ham(raw, w, h, HamOptions{}, 256, false, 0);
    EXPECT_GT(cliffs.stats.ham_max, 10 * r.stats.ham_max) << path;
  }
}

}  // namespace
}  // namespace splatkit::terrain
