// A synthetic terrain heightmap for ham.sh, generated row by row (memory independent of its
// size): four octaves of smooth value noise (hashed lattice, smoothstep interpolation) in metres,
// float32. Writes an uncompressed stripped TIFF through OpenImageIO, or raw little-endian rows
// to standard output ("-") for build-ham --raw W,H,float32.
// usage: make_heightmap WIDTH HEIGHT OUT.tif|-
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

float lattice(int64_t x, int64_t y, uint32_t seed) {
  uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^ seed;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return float(h >> 40) / float(1 << 24);
}

// Value noise at (x, y) / period.
void noise_row(int64_t y, int64_t width, int64_t period, uint32_t seed, float amplitude,
               float* row) {
  const int64_t gy = y / period;
  float ty = float(y % period) / float(period);
  ty = ty * ty * (3 - 2 * ty);
  for (int64_t x0 = 0; x0 < width; x0 += period) {
    const int64_t gx = x0 / period;
    const float a = lattice(gx, gy, seed), b = lattice(gx + 1, gy, seed);
    const float c = lattice(gx, gy + 1, seed), d = lattice(gx + 1, gy + 1, seed);
    const float top = a + (c - a) * ty, bottom = b + (d - b) * ty;
    const int64_t end = std::min(width, x0 + period);
    for (int64_t x = x0; x < end; ++x) {
      float tx = float(x - x0) / float(period);
      tx = tx * tx * (3 - 2 * tx);
      row[x] += amplitude * (top + (bottom - top) * tx);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: make_heightmap WIDTH HEIGHT OUT.tif|-\n");
    return 1;
  }
  const int64_t w = std::atoll(argv[1]), h = std::atoll(argv[2]);
  const std::string out_path = argv[3];
  std::unique_ptr<OIIO::ImageOutput> out;
  if (out_path != "-") {
    out = OIIO::ImageOutput::create(out_path);
    OIIO::ImageSpec spec(int(w), int(h), 1, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "none");
    spec.attribute("tiff:RowsPerStrip", 64);
    if (!out || !out->open(out_path, spec)) {
      std::fprintf(stderr, "make_heightmap: %s\n", OIIO::geterror().c_str());
      return 2;
    }
  }
  const int64_t band = 64;
  std::vector<float> rows(std::size_t(w * band));
  for (int64_t y0 = 0; y0 < h; y0 += band) {
    const int64_t n = std::min(band, h - y0);
    std::fill(rows.begin(), rows.end(), 0.0f);
    for (int64_t r = 0; r < n; ++r) {
      float* row = rows.data() + r * w;
      noise_row(y0 + r, w, 1024, 1, 2000.0f, row);
      noise_row(y0 + r, w, 256, 2, 600.0f, row);
      noise_row(y0 + r, w, 64, 3, 150.0f, row);
      noise_row(y0 + r, w, 16, 4, 30.0f, row);
    }
    if (out) {
      if (!out->write_scanlines(int(y0), int(y0 + n), 0, OIIO::TypeDesc::FLOAT, rows.data())) {
        std::fprintf(stderr, "make_heightmap: %s\n", out->geterror().c_str());
        return 2;
      }
    } else if (std::fwrite(rows.data(), 4, std::size_t(n * w), stdout) != std::size_t(n * w)) {
      return 2;
    }
  }
  if (out && !out->close()) return 2;
  return 0;
}
