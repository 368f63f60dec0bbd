#include "terrain/tess_factors.h"

#include <algorithm>
#include <cmath>

namespace splatkit::terrain {

namespace {

Vec3f scene_point(const TerrainFrame& f, double x, double y, double z) {
  return {float(x * f.sx), float(-y * f.sy), float(z)};
}

// Whether the box [x0, x1] × [y0, y1] (texels) × [z0, z1] lies wholly outside the view.
bool outside(const TerrainFrame& f, const TileExtent& e, double z0, double z1,
             const render::Projection& p) {
  int left = 0, right = 0, above = 0, below = 0, behind = 0;
  for (int i = 0; i < 8; ++i) {
    const Vec3f c = p.to_camera(scene_point(f, (i & 1) ? double(e.x1) : double(e.x0),
                                            (i & 2) ? double(e.y1) : double(e.y0),
                                            (i & 4) ? z1 : z0));
    if (c.z <= p.near) {
      ++behind;
      continue;
    }
    const float u = p.cx + p.focal_px * c.x / c.z, v = p.cy + p.focal_px * c.y / c.z;
    left += u < 0;
    right += u > float(p.width);
    above += v < 0;
    below += v > float(p.height);
  }
  return behind == 8 || left + behind == 8 || right + behind == 8 || above + behind == 8 ||
         below + behind == 8;
}

}  // namespace

float tile_t_max(float ham_max, double ham_ref) {
  if (!(ham_ref > 0) || !(ham_max > 0)) return 1.0f;
  return float(std::clamp(1.0 + 63.0 * std::sqrt(double(ham_max) / ham_ref), 1.0, 64.0));
}

double tile_curvature(float ham_max) { return ham_max > 0 ? double(ham_max) / 64.0 : 0.0; }

int tess_factor(float t_max, double peak, const Vec3f& point, const render::Projection& camera,
                double d_max, const TessSettings& s, double curvature, int64_t texels) {
  const Vec3f d3 = point - camera.eye;
  const double d = std::max(1e-9, double(std::sqrt(dot(d3, d3))));
  const double projected = double(camera.focal_px) * std::max(0.0, peak) / d;
  const double t_min =
      std::clamp(std::log2(std::max(projected, 1e-30) / double(s.error_px)), 1.0, double(t_max));
  double t = t_max;
  if (d >= d_max) {
    const double d_min = std::sqrt(double(t_max) / t_min) * d_max;
    t = d <= d_min ? double(t_max) * d_max * d_max / (d * d) : t_min;
  }
  // Past n (at most 64) the segments would be shorter than a texel: nothing more to show.
  const double full = double(std::clamp<int64_t>(texels, 1, 64));
  // A height error is vertical: seen at angle θ from the vertical it spans sin θ of its length.
  const double sin_view = std::sqrt(std::max(0.0, 1.0 - double(d3.z) * double(d3.z) / (d * d)));
  if (curvature > 0)
    t = std::max(t, full * std::sqrt(double(camera.focal_px) * curvature * sin_view /
                                     (8.0 * d * s.error_px)));
  return std::clamp(int(std::ceil(std::min(t, full) - 1e-6)), 1, 64);
}

TileExtent tile_extent(const HamTiles& t, int64_t tx, int64_t ty) {
  return {tx * t.tile, std::min((tx + 1) * t.tile, t.width - 1), ty * t.tile,
          std::min((ty + 1) * t.tile, t.height - 1)};
}

std::vector<TileFactors> tess_factors(const HamTiles& t, const TerrainFrame& f,
                                      const render::Projection& camera, const TessSettings& s,
                                      HeightAt height, const void* context) {
  std::vector<TileFactors> out(t.size());
  const double diag = double(t.tile) * std::hypot(f.sx, f.sy);
  const double d_max = double(s.d_max_tiles) * diag;
  auto index = [&](int64_t tx, int64_t ty) { return std::size_t(ty * t.tiles_x + tx); };
  // An edge from texel (ax, ay) to (bx, by) (a before b), between tiles i and j (j = i when the
  // edge is on the map's border): the same inputs from either side.
  auto edge = [&](std::size_t i, std::size_t j, int64_t ax, int64_t ay, int64_t bx, int64_t by) {
    const float t_max = std::max(tile_t_max(t.ham_max[i], f.ham_ref),
                                 tile_t_max(t.ham_max[j], f.ham_ref));
    const double peak = std::max(double(t.h_max[i]), double(t.h_max[j])) - f.h_min;
    const double kappa = std::max(tile_curvature(t.ham_max[i]), tile_curvature(t.ham_max[j]));
    const double mx = 0.5 * double(ax + bx), my = 0.5 * double(ay + by);
    const Vec3f mid = scene_point(f, mx, my, height(context, mx, my));
    return tess_factor(t_max, peak, mid, camera, d_max, s, kappa, (bx - ax) + (by - ay));
  };
  for (int64_t ty = 0; ty < t.tiles_y; ++ty)
    for (int64_t tx = 0; tx < t.tiles_x; ++tx) {
      const std::size_t i = index(tx, ty);
      const TileExtent e = tile_extent(t, tx, ty);
      if (e.x1 <= e.x0 || e.y1 <= e.y0) continue;  // a one-texel sliver at the border: none
      if (outside(f, e, f.h_min, double(t.h_max[i]), camera)) continue;
      TileFactors& tf = out[i];
      const std::size_t north = ty > 0 ? index(tx, ty - 1) : i;
      const std::size_t south = ty + 1 < t.tiles_y ? index(tx, ty + 1) : i;
      const std::size_t west = tx > 0 ? index(tx - 1, ty) : i;
      const std::size_t east = tx + 1 < t.tiles_x ? index(tx + 1, ty) : i;
      // A neighbour that is a one-texel sliver contributes nothing: the edge is the border.
      auto real = [&](std::size_t j, int64_t nx, int64_t ny) {
        const TileExtent n = tile_extent(t, nx, ny);
        return n.x1 > n.x0 && n.y1 > n.y0 ? j : i;
      };
      tf.edge[0] = edge(i, real(north, tx, ty - 1), e.x0, e.y0, e.x1, e.y0);
      tf.edge[1] = edge(i, tx + 1 < t.tiles_x ? real(east, tx + 1, ty) : i, e.x1, e.y0, e.x1, e.y1);
      tf.edge[2] = edge(i, ty + 1 < t.tiles_y ? real(south, tx, ty + 1) : i, e.x0, e.y1, e.x1, e.y1);
      tf.edge[3] = edge(i, real(west, tx - 1, ty), e.x0, e.y0, e.x0, e.y1);
      const double cx = 0.5 * double(e.x0 + e.x1), cy = 0.5 * double(e.y0 + e.y1);
      tf.inner = tess_factor(tile_t_max(t.ham_max[i], f.ham_ref), double(t.h_max[i]) - f.h_min,
                             scene_point(f, cx, cy, t.h_max[i]), camera, d_max, s,
                             tile_curvature(t.ham_max[i]), std::max(e.x1 - e.x0, e.y1 - e.y0));
    }
  return out;
}

}  // namespace splatkit::terrain
