// The terrain renderer behind splat-view --terrain: per frame, the tessellation factors of every
// tile (tess_factors.h), the tessellated tiles displaced by the heightmap (tessellate_tile.h),
// rasterised with a depth buffer, with an optional wireframe overlay. Triangles reaching behind
// the near plane are not drawn. The triangles give each pixel its depth and the texel it shows
// (perspective-correct on the triangle's plane); the pixel is then shaded from the heightmap at
// that texel, not from the triangle's vertices: Lambert on TerrainMap::normal, the colour of the
// bilinear height (a hypsometric ramp from the map's lowest to its highest height). The image's
// detail is the map's whatever the tessellation; the tessellation moves silhouettes, occlusion
// and depth. The triangles are drawn on one thread, the pixels shaded in parallel, each on its
// own: the same bytes whatever the thread count.
#pragma once

#include <array>
#include <cstdint>

#include "render/camera.h"
#include "render/framebuffer.h"
#include "terrain/ham_tiles.h"
#include "terrain/tess_factors.h"
#include "terrain/terrain_map.h"

namespace splatkit::terrain {

struct TerrainRenderOptions {
  TessSettings tess;
  bool wireframe = false;
  Vec3f background{0.62f, 0.74f, 0.86f};  // sRGB
};

struct TerrainRenderStats {
  uint64_t tiles = 0, visible_tiles = 0;
  uint64_t triangles = 0;            // drawn (tessellated in visible tiles)
  uint64_t triangles_at_64 = 0;      // every tile with factor 64 everywhere (2·64² each)
  uint64_t triangles_behind = 0;     // skipped: reaching behind the near plane
  std::array<uint64_t, 65> histogram{};  // edge and inner factors of the visible tiles
};

// The scene's bounding sphere for default cameras.
render::BoundingSphere terrain_bounds(const TerrainMap& map, const TerrainFrame& frame);

TerrainRenderStats render_terrain(const TerrainMap& map, const HamTiles& tiles,
                                  const TerrainFrame& frame, const render::Camera& camera,
                                  const TerrainRenderOptions& options, render::Framebuffer& out);

}  // namespace splatkit::terrain
