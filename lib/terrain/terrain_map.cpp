#include "terrain/terrain_map.h"

#include <algorithm>
#include <cmath>

#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "terrain/direct_tiff.h"
#include "terrain/fill_voids.h"
#include "terrain/tiff_geo_tags.h"
#include "terrain/raw_heightmap.h"
#include "terrain/terrain_images.h"

namespace splatkit::terrain {

double TerrainMap::sample(double x, double y) const {
  x = std::clamp(x, 0.0, double(width - 1));
  y = std::clamp(y, 0.0, double(height - 1));
  const auto x0 = int64_t(x), y0 = int64_t(y);
  const int64_t x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const double fx = x - double(x0), fy = y - double(y0);
  const double top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
  const double bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
  return top + (bottom - top) * fy;
}

Vec3f TerrainMap::normal(double x, double y, double sx, double sy) const {
  x = std::clamp(x, 0.0, double(width - 1));
  y = std::clamp(y, 0.0, double(height - 1));
  const auto x0 = int64_t(x), y0 = int64_t(y);
  if (x0 >= 1 && x0 + 2 < width && y0 >= 1 && y0 + 2 < height) {
    // Inside: the same differences of bilinear samples, from the 4 × 4 texels around (x, y)
    // directly (the blend of the four texels' central differences), without the clamps.
    const float* r0 = heights.data() + std::size_t(y0 * width + x0);
    const float *rm = r0 - width, *r1 = r0 + width, *r2 = r1 + width;
    const double fx = x - double(x0), fy = y - double(y0);
    const double gx0 = (1 - fx) * (r0[1] - r0[-1]) + fx * (r0[2] - r0[0]);
    const double gx1 = (1 - fx) * (r1[1] - r1[-1]) + fx * (r1[2] - r1[0]);
    const double gy0 = (1 - fx) * (r1[0] - rm[0]) + fx * (r1[1] - rm[1]);
    const double gy1 = (1 - fx) * (r2[0] - r0[0]) + fx * (r2[1] - r0[1]);
    const double dhdx = ((1 - fy) * gx0 + fy * gx1) * 0.5;
    const double dhdy = ((1 - fy) * gy0 + fy * gy1) * 0.5;
    return normalized(Vec3f{float(-dhdx / sx), float(dhdy / sy), 1.0f});
  }
  // Near the border the step shrinks to what the map holds (a plane stays exact there).
  const double xa = std::max(0.0, x - 1), xb = std::min(double(width - 1), x + 1);
  const double ya = std::max(0.0, y - 1), yb = std::min(double(height - 1), y + 1);
  const double dhdx = xb > xa ? (sample(xb, y) - sample(xa, y)) / (xb - xa) : 0.0;
  const double dhdy = yb > ya ? (sample(x, yb) - sample(x, ya)) / (yb - ya) : 0.0;
  return normalized(Vec3f{float(-dhdx / sx), float(dhdy / sy), 1.0f});
}

std::unique_ptr<HeightmapSource> open_heightmap(const std::string& path, const std::string& raw) {
  if (!raw.empty()) return open_raw_heightmap(path, parse_raw_layout(raw));
  if (path == "-") throw_usage("a heightmap may be '-' only with --raw (other formats need a file)");
  const std::string ext = lower_extension(path);
  if (ext == "hgt") return open_hgt(path);
  if (ext == "tif" || ext == "tiff") {  // uncompressed single-band: read directly
    if (auto direct = open_direct_tiff(path, read_tiff_geo_tags_file(path))) return direct;
  }
  return open_image_heightmap(path);
}

TerrainMap load_terrain_map(HeightmapSource& source, std::optional<double> nodata,
                            double z_scale) {
  const HeightmapInfo& info = source.info();
  TerrainMap m;
  m.width = info.width;
  m.height = info.height;
  m.heights.resize(std::size_t(m.width * m.height));
  const bool has_nodata = nodata.has_value() || info.has_nodata;
  VoidFiller filler(source, has_nodata, float(nodata ? *nodata : info.nodata),
                    default_lookahead(m.width));
  for (int64_t y = 0; y < m.height; ++y) filler.next(m.heights.data() + y * m.width);
  for (float& h : m.heights) h = float(h * z_scale);
  const auto [lo, hi] = std::minmax_element(m.heights.begin(), m.heights.end());
  m.h_min = *lo;
  m.h_max = *hi;
  return m;
}

}  // namespace splatkit::terrain
