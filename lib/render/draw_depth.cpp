#include "render/draw_depth.h"

#include <algorithm>

namespace splatkit::render {

PixelRect draw_depth(const RenderScene& scene, const uint32_t* indices, std::size_t count,
                     const Projection& projection, bool cull_backfaces, DepthPyramid* target,
                     DepthPassScratch& s, SplatBounds* bounds) {
  s.positions.resize(count);
  s.normals.resize(count);
  s.radii.resize(count);
  const bool ellipses = !scene.axes.empty();
  if (ellipses) {
    s.axes.resize(count);
    s.minor_radii.resize(count);
  }
  for (std::size_t k = 0; k < count; ++k) {
    const uint32_t i = indices[k];
    s.positions[k] = scene.positions[i];
    s.normals[k] = scene.normals[i];
    s.radii[k] = scene.radii[i];
    if (ellipses) {
      s.axes[k] = scene.axes[i];
      s.minor_radii[k] = scene.minor_radii[i];
    }
  }
  DrawList d;
  d.count = count;
  d.positions = s.positions.data();
  d.normals = s.normals.data();
  d.radii = s.radii.data();
  if (ellipses) {
    d.axes = s.axes.data();
    d.minor_radii = s.minor_radii.data();
  }
  s.rasters.resize(count);
  setup_splats(d, projection, SetupOptions{cull_backfaces}, 0, count, s.rasters.data());
  if (bounds)
    for (std::size_t k = 0; k < count; ++k) {
      const SplatRaster& r = s.rasters[k];
      bounds[k] = {r.x0, r.y0, r.x1, r.y1, r.zmin};
    }
  PixelRect dirty;
  if (!target) return dirty;
  DepthPyramid& pyramid = *target;
  const int width = projection.width, height = projection.height;
  for (const SplatRaster& r : s.rasters) {
    if (!r.drawn()) continue;
    const float far = r.zmax * 1.001f;
    // The depth bound at pixel (x, y), or -1 when the pixel is not safely inside the disc.
    auto depth_at = [&](int x, int y) {
      const float di = float(x - r.x0), dj = float(y - r.y0);
      const float l = r.l[0] * di + r.l[1] * dj + r.l[2];
      const float u = r.u[0] * di + r.u[1] * dj + r.u[2];
      const float v = r.v[0] * di + r.v[1] * dj + r.v[2];
      const float l2 = l * l;
      if (!(l2 >= 1e-6f && u * u + v * v <= 0.98f * l2)) return -1.0f;
      return std::min(far, r.nc / l * 1.001f);
    };
    // Nothing to lower when every depth already there is at most what the splat would write
    // (the upper levels may be stale, but stale cells only overstate).
    const float lowest = kDepthCellShift == 0 ? far : r.zmin;
    if (lowest >= pyramid.max_depth(cells_of(PixelRect{r.x0, r.y0, r.x1, r.y1}))) continue;
    PixelRect written;
    if constexpr (kDepthCellShift == 0) {
      // Per row, the pixels inside the disc form one run (the disc's rays are a convex cone,
      // and a row a line): found from each end, then every pixel between written. Tests only
      // the pixels outside the run. The ends are tested directly (not accumulated along the
      // row); a run whose ends disagree on the sign of L (a grazing disc, the cone's two
      // halves) is tested pixel by pixel.
      auto at = [&](int x, float dj, float& l) {
        const float di = float(x - r.x0);
        l = r.l[0] * di + r.l[1] * dj + r.l[2];
        const float u = r.u[0] * di + r.u[1] * dj + r.u[2];
        const float v = r.v[0] * di + r.v[1] * dj + r.v[2];
        const float l2 = l * l;
        return l2 >= 1e-6f && u * u + v * v <= 0.98f * l2;
      };
      for (int y = r.y0; y <= r.y1; ++y) {
        const float dj = float(y - r.y0);
        float la = 0, lb = 0;
        int a = r.x0;
        while (a <= r.x1 && !at(a, dj, la)) ++a;
        if (a > r.x1) continue;
        int b = r.x1;
        while (b > a && !at(b, dj, lb)) --b;
        if (b == a) lb = la;
        if ((la > 0) == (lb > 0)) {
          pyramid.lower_run(a, b, y, far);
        } else {
          for (int x = a; x <= b; ++x)
            if (at(x, dj, la)) pyramid.lower(x, y, far);
        }
        written.extend(PixelRect{a, y, b, y});
      }
      dirty.extend(written);
      continue;
    }
    const PixelRect cells = cells_of(PixelRect{r.x0, r.y0, r.x1, r.y1});
    for (int cy = cells.y0; cy <= cells.y1; ++cy) {
      const int y0 = cy << kDepthCellShift, y1 = std::min(y0 + kDepthCell - 1, height - 1);
      if (y0 < r.y0 || y1 > r.y1) continue;
      for (int cx = cells.x0; cx <= cells.x1; ++cx) {
        const int x0 = cx << kDepthCellShift, x1 = std::min(x0 + kDepthCell - 1, width - 1);
        if (x0 < r.x0 || x1 > r.x1) continue;
        float depth;
        if constexpr (kDepthCellShift == 0) {
          depth = depth_at(x0, y0);
          if (depth < 0) continue;
        } else {
          const float a = depth_at(x0, y0), b = depth_at(x1, y0), c = depth_at(x0, y1),
                      e = depth_at(x1, y1);
          if (a < 0 || b < 0 || c < 0 || e < 0) continue;
          depth = std::max(std::max(a, b), std::max(c, e));
        }
        pyramid.lower(cx, cy, depth);
        written.extend(PixelRect{cx, cy, cx, cy});
      }
    }
    dirty.extend(written);
  }
  return dirty;
}

}  // namespace splatkit::render
