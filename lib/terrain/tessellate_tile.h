// The tessellation of one terrain tile, as a GPU's quad-domain tessellator with integer
// partitioning would make it: each edge cut into its factor's equal parts, the interior a grid
// of inner × inner cells of which the outer ring is replaced by strips stitching the inner grid
// to the edges. Vertices are texel coordinates; a vertex on an edge depends only on that edge's
// endpoints and factor, so two tiles sharing an edge with the same factor produce the same
// vertices bit for bit (no cracks).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "terrain/tess_factors.h"

namespace splatkit::terrain {

struct TileMesh {
  std::vector<std::array<double, 2>> vertices;  // texel coordinates (x, y)
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Appends the tile's mesh (extent `e`, factors `f`, all ≥ 1) to `mesh`.
void tessellate_tile(const TileExtent& e, const TileFactors& f, TileMesh& mesh);

// Triangles tessellate_tile makes for these factors (for --stats), without making them.
uint64_t tile_triangle_count(const TileFactors& f);

}  // namespace splatkit::terrain
