#include "terrain/render_terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <oneapi/tbb/parallel_for.h>

#include "terrain/tessellate_tile.h"

namespace splatkit::terrain {

namespace {

double height_at(const void* context, double x, double y) {
  return static_cast<const TerrainMap*>(context)->sample(x, y);
}

// Colour by height (sRGB): lowland green, brown, grey rock, snow.
Vec3f hypsometric(float t) {
  static const Vec3f stops[] = {{0.25f, 0.45f, 0.22f}, {0.55f, 0.55f, 0.30f},
                                {0.50f, 0.40f, 0.30f}, {0.55f, 0.53f, 0.52f},
                                {0.95f, 0.95f, 0.97f}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  const int i = std::min(3, int(t));
  const float f = t - float(i);
  return stops[i] * (1 - f) + stops[i + 1] * f;
}

struct ScreenVertex {
  float x, y, inv_z;  // pixel coordinates, 1 / camera depth
  float u, v;         // texel coordinates
  bool behind;
};

uint8_t to8(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

render::BoundingSphere terrain_bounds(const TerrainMap& m, const TerrainFrame& f) {
  const Vec3f lo{0.0f, float(-double(m.height - 1) * f.sy), m.h_min};
  const Vec3f hi{float(double(m.width - 1) * f.sx), 0.0f, m.h_max};
  const Vec3f c = (lo + hi) * 0.5f;
  const Vec3f d = hi - c;
  return {c, std::sqrt(dot(d, d))};
}

TerrainRenderStats render_terrain(const TerrainMap& map, const HamTiles& tiles,
                                  const TerrainFrame& frame, const render::Camera& camera,
                                  const TerrainRenderOptions& o, render::Framebuffer& out) {
  const render::Projection p = render::make_projection(camera);
  const int W = out.width, H = out.height;
  std::vector<float> zbuf(std::size_t(W) * H, 0.0f);  // 1/depth, 0 = nothing
  // The texel each pixel shows (perspective-correct on its triangle), shaded after all tiles
  // are drawn: once per pixel, from the map itself rather than the coarse triangles' vertices.
  std::vector<float> tex_u(std::size_t(W) * H, 0.0f), tex_v(std::size_t(W) * H, 0.0f);
  std::vector<uint8_t> on_edge(o.wireframe ? std::size_t(W) * H : 0, 0);
  TerrainRenderStats stats;
  const std::vector<TileFactors> factors =
      tess_factors(tiles, frame, p, o.tess, height_at, &map);
  const Vec3f light = normalized(Vec3f{0.35f, -0.45f, 0.80f});
  const float range = std::max(1e-6f, map.h_max - map.h_min);

  TileMesh mesh;
  std::vector<ScreenVertex> sv;
  for (int64_t ty = 0; ty < tiles.tiles_y; ++ty)
    for (int64_t tx = 0; tx < tiles.tiles_x; ++tx) {
      const std::size_t i = std::size_t(ty * tiles.tiles_x + tx);
      const TileExtent e = tile_extent(tiles, tx, ty);
      if (e.x1 <= e.x0 || e.y1 <= e.y0) continue;
      ++stats.tiles;
      stats.triangles_at_64 += 2 * 64 * 64;
      const TileFactors& f = factors[i];
      if (!f.visible()) continue;
      ++stats.visible_tiles;
      for (int k : f.edge) ++stats.histogram[std::size_t(k)];
      ++stats.histogram[std::size_t(f.inner)];
      mesh.vertices.clear();
      mesh.triangles.clear();
      tessellate_tile(e, f, mesh);
      stats.triangles += mesh.triangles.size();
      sv.resize(mesh.vertices.size());
      for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const double x = mesh.vertices[v][0], y = mesh.vertices[v][1];
        const double h = map.sample(x, y);
        const Vec3f world{float(x * frame.sx), float(-y * frame.sy), float(h)};
        const Vec3f c = p.to_camera(world);
        ScreenVertex& s = sv[v];
        s.behind = c.z <= p.near;
        s.inv_z = s.behind ? 0.0f : 1.0f / c.z;
        s.x = p.cx + p.focal_px * c.x * s.inv_z;
        s.y = p.cy + p.focal_px * c.y * s.inv_z;
        s.u = float(x);
        s.v = float(y);
      }
      for (const auto& t : mesh.triangles) {
        const ScreenVertex &a = sv[t[0]], &b = sv[t[1]], &c = sv[t[2]];
        if (a.behind || b.behind || c.behind) {
          ++stats.triangles_behind;
          continue;
        }
        const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (std::abs(area) < 1e-12f) continue;
        const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
        const int x1 = std::min(W - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
        const int y1 = std::min(H - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
        if (x0 > x1 || y0 > y1) continue;
        const float inv_area = 1.0f / area;
        // Edge lengths in pixels, for the wireframe's distance to each edge.
        const float la = std::hypot(c.x - b.x, c.y - b.y), lb = std::hypot(a.x - c.x, a.y - c.y);
        const float lc = std::hypot(b.x - a.x, b.y - a.y);
        for (int py = y0; py <= y1; ++py)
          for (int px = x0; px <= x1; ++px) {
            const float qx = float(px) + 0.5f, qy = float(py) + 0.5f;
            const float wa = ((b.x - qx) * (c.y - qy) - (b.y - qy) * (c.x - qx)) * inv_area;
            const float wb = ((c.x - qx) * (a.y - qy) - (c.y - qy) * (a.x - qx)) * inv_area;
            const float wc = 1.0f - wa - wb;
            if (wa < 0 || wb < 0 || wc < 0) continue;
            const float iz = wa * a.inv_z + wb * b.inv_z + wc * c.inv_z;
            const std::size_t at = std::size_t(py) * W + px;
            if (iz <= zbuf[at]) continue;
            zbuf[at] = iz;
            // Perspective-correct weights: the texel under the pixel on the triangle's plane.
            const float pa = wa * a.inv_z / iz, pb = wb * b.inv_z / iz, pc = 1.0f - pa - pb;
            tex_u[at] = a.u * pa + b.u * pb + c.u * pc;
            tex_v[at] = a.v * pa + b.v * pb + c.v * pc;
            if (o.wireframe) {
              const float two_area = std::abs(area);
              const float d = std::min({wa * two_area / std::max(la, 1e-6f),
                                        wb * two_area / std::max(lb, 1e-6f),
                                        wc * two_area / std::max(lc, 1e-6f)});
              on_edge[at] = d < 0.6f;
            }
          }
      }
    }

  // Every pixel on its own: the same bytes whatever the threads.
  auto shade = [&](std::size_t k) {
    const bool hit = zbuf[k] > 0;
    Vec3f c = o.background, nk{0, 0, 0};
    if (hit) {
      // Lambert on the map's own normal, the colour of the map's own height, at the pixel's texel.
      const double u = tex_u[k], v = tex_v[k];
      nk = map.normal(u, v, frame.sx, frame.sy);
      const float lambert = std::max(0.0f, dot(nk, light));
      c = hypsometric((float(map.sample(u, v)) - map.h_min) / range) * (0.45f + 0.65f * lambert);
      if (o.wireframe && on_edge[k]) c = c * 0.25f + Vec3f{0.05f, 0.05f, 0.08f} * 0.75f;
    }
    if (out.planes.rgb8) {
      out.rgb8[3 * k] = to8(c.x);
      out.rgb8[3 * k + 1] = to8(c.y);
      out.rgb8[3 * k + 2] = to8(c.z);
    }
    if (out.planes.float_color) {
      const float a = hit ? 1.0f : 0.0f;
      out.rgba[4 * k] = a * srgb_to_linear(c.x);
      out.rgba[4 * k + 1] = a * srgb_to_linear(c.y);
      out.rgba[4 * k + 2] = a * srgb_to_linear(c.z);
      out.rgba[4 * k + 3] = a;
    }
    if (out.planes.aovs) {
      out.depth[k] = hit ? 1.0f / zbuf[k] : std::numeric_limits<float>::infinity();
      out.alpha[k] = hit ? 1.0f : 0.0f;
      for (int j = 0; j < 3; ++j) out.normal[3 * k + std::size_t(j)] = hit ? nk[j] : 0.0f;
    }
    if (out.planes.surface_ids) out.surface_id[k] = render::kNoSurfaceId;
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int py = rows.begin(); py < rows.end(); ++py)
      for (int px = 0; px < W; ++px) shade(std::size_t(py) * std::size_t(W) + std::size_t(px));
  });
  return stats;
}

}  // namespace splatkit::terrain
