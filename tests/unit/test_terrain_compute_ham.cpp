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

namespace splatkit::terrain {
namespace {

class MemorySource final : public HeightmapSource {
 public:
  MemorySource(std::vector<float> data, int64_t w, int64_t h, int64_t band_rows = 64)
      : data_(std::move(data)) {
    info_.width = w;
    info_.height = h;
    info_.band_rows = band_rows;
  }
  void read_rows(int64_t rows, float* out) override {
    std::memcpy(out, data_.data() + next_ * info_.width, std::size_t(rows * info_.width) * 4);
    next_ += rows;
  }
  void set_nodata(float v) {
    info_.has_nodata = true;
    info_.nodata = v;
  }

 private:
  std::vector<float> data_;
  int64_t next_ = 0;
};

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
  std::vector<double> ham;
  std::vector<double> ham_max, h_max;
  std::vector<uint32_t> x, y;
};

// `filled`: the heights after void filling (fill_row_voids is tested on its own below).
Reference reference(const std::vector<float>& filled, int64_t w, int64_t h, int64_t T) {
  std::vector<double> hd(filled.begin(), filled.end());
  Reference r;
  r.ham = sobel_ref(sobel_ref(hd, w, h), w, h);
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

std::vector<float> filled_copy(const std::vector<float>& v, int64_t w, int64_t h, bool nd,
                               float nodata);

std::vector<float> filled_copy(const std::vector<float>& v, int64_t w, int64_t h, bool nd,
                               float nodata) {
  MemorySource src(v, w, h);
  if (nd) src.set_nodata(nodata);
  VoidFiller filler(src, nd, nodata, default_lookahead(w));
  std::vector<float> out(v.size());
  for (int64_t y = 0; y < h; ++y) filler.next(out.data() + y * w);
  return out;
}

struct HamRun {
  HamTiles tiles;
  HamStats stats;
  std::vector<float> ham;
};

HamRun run_ham(const std::vector<float>& data, int64_t w, int64_t h, HamOptions o, int64_t band_rows = 64,
        bool nodata = false, float nodata_value = 0) {
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
                300 * std::exp(-(std::pow(double(x) - 40, 2) + std::pow(double(y) - 30, 2)) / 200)) +
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
  const std::vector<float> f = filled_copy(v, w, h, false, 0);
  expect_matches(r, reference(f, w, h, 64), "void rows");
  // Filled rows stay within the heights of the rows around them.
  for (int64_t y : {0, 1, 6, 11})
    for (int64_t x = 0; x < w; ++x) {
      const float value = f[std::size_t(y * w + x)];
      EXPECT_GE(value, *std::min_element(v.begin() + 2 * w, v.begin() + 11 * w)) << y;
      EXPECT_LE(value, *std::max_element(v.begin() + 2 * w, v.begin() + 11 * w)) << y;
    }
  EXPECT_EQ(r.tiles.voids[0], uint32_t(4 * w));
}

TEST(TerrainFillVoids, RunsBecomeLinesBetweenTheirNeighbours) {
  std::vector<float> row = {-32768, 10, -32768, -32768, -32768, 20, NAN, -32768};
  EXPECT_EQ(fill_row_voids(row.data(), int64_t(row.size()), true, -32768), 6);
  EXPECT_EQ(row, (std::vector<float>{10, 10, 12.5f, 15, 17.5f, 20, 20, 20}));
  std::vector<float> none = {NAN, NAN};
  EXPECT_EQ(fill_row_voids(none.data(), 2, false, 0), 2);
}

// Real SRTM: the library's reader and the reference agree, and the HAM over filled voids stays
// within the range of the void-free terrain around them (unfilled, the voids give HAM near 7e5).
TEST(TerrainComputeHam, RealSrtmWithVoids) {
  for (const char* name : {"mt_fuji_90m.tif", "mt_rainier_90m.tif", "mt_everest_90m.tif"}) {
    const std::string path = std::string("/work/shared/data/dem/") + name;
    if (FILE* f = std::fopen(path.c_str(), "rb")) std::fclose(f);
    else GTEST_SKIP() << path << " not present";
    auto src = open_image_heightmap(path);
    const int64_t w = src->info().width, h = src->info().height;
    ASSERT_TRUE(src->info().has_nodata);
    EXPECT_EQ(src->info().nodata, -32768);
    std::vector<float> raw(std::size_t(w * h));
    src->read_rows(h, raw.data());
    const HamRun r = run_ham(raw, w, h, HamOptions{}, 256, true, -32768);
    expect_matches(r, reference(filled_copy(raw, w, h, true, -32768), w, h, 64), name);
    // Texels whose HAM depends on a filled sample (within 5 texels of a void: the void-edge
    // samples replaced too, then two Sobel passes) against the HAM of the texels that do not,
    // in the same tile and the 8 around it.
    const HamTiles& t = r.tiles;
    std::vector<uint8_t> row_near(std::size_t(w * h), 0), affected(std::size_t(w * h), 0);
    for (int64_t y = 0; y < h; ++y)  // dilation by 5 texels: rows, then columns
      for (int64_t x = 0; x < w; ++x)
        if (raw[std::size_t(y * w + x)] == -32768)
          for (int64_t xx = std::max<int64_t>(0, x - 5); xx <= std::min(w - 1, x + 5); ++xx)
            row_near[std::size_t(y * w + xx)] = 1;
    for (int64_t y = 0; y < h; ++y)
      for (int64_t x = 0; x < w; ++x)
        if (row_near[std::size_t(y * w + x)])
          for (int64_t yy = std::max<int64_t>(0, y - 5); yy <= std::min(h - 1, y + 5); ++yy)
            affected[std::size_t(yy * w + x)] = 1;
    std::vector<float> clean(t.size(), 0.0f), filled_max(t.size(), 0.0f);
    for (int64_t y = 0; y < h; ++y)
      for (int64_t x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(y * w + x), k = std::size_t((y / 64) * t.tiles_x + x / 64);
        float& m = affected[i] ? filled_max[k] : clean[k];
        m = std::max(m, r.ham[i]);
      }
    double worst = 0;
    std::size_t void_tiles = 0;
    for (int64_t ty = 0; ty < t.tiles_y; ++ty)
      for (int64_t tx = 0; tx < t.tiles_x; ++tx) {
        const std::size_t i = std::size_t(ty * t.tiles_x + tx);
        if (filled_max[i] == 0) continue;
        ++void_tiles;
        float around = 0;
        for (int64_t y = std::max<int64_t>(0, ty - 1); y <= std::min(t.tiles_y - 1, ty + 1); ++y)
          for (int64_t x = std::max<int64_t>(0, tx - 1); x <= std::min(t.tiles_x - 1, tx + 1);
               ++x)
            around = std::max(around, clean[std::size_t(y * t.tiles_x + x)]);
        if (around > 0) worst = std::max(worst, double(filled_max[i]) / double(around));
      }
    EXPECT_GT(void_tiles, 0u) << name;
    // No spike: within twice the terrain's own HAM around the void (measured: 1.2 to 1.8 on
    // these tiles); the same voids unfilled reach hundreds of times it (checked below).
    EXPECT_LE(worst, 2.0) << name << ": HAM over filled voids against the terrain around them";
    std::printf("%s: filled-void HAM / surrounding terrain HAM, worst tile %.3f\n", name, worst);
    // Unfilled, the same voids would be cliffs: the check above can fail.
    const HamRun cliffs = run_ham(raw, w, h, HamOptions{}, 256, false, 0);
    EXPECT_GT(cliffs.stats.ham_max, 10 * r.stats.ham_max) << name;
  }
}

}  // namespace
}  // namespace splatkit::terrain
