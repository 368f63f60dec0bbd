// Where a heightmap's texels lie in the file's own coordinates (splat-view --terrain's cameras,
// splat-info's bounds).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace splatkit::apps {

// The file's coordinates of the texels: X = x0 + column * dx, Y = y0 + row * dy (dy < 0 for a
// north-up map), from the georeferencing the tiles carry (GeoTIFF tiepoint and pixel scale, with
// the half-texel shift of PixelIsArea; a north-up ModelTransformation; SRTM's origin); without
// one, X is the column and Y minus the row. Heights are the file's, times --z-scale in the view.
struct TexelFrame {
  double x0 = 0, dx = 1, y0 = 0, dy = -1;
  std::string name = "texels: x = column, y = -row, z = height";
};

TexelFrame texel_frame(const nlohmann::json& georef);

}  // namespace splatkit::apps
