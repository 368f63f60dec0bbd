// splat-view --terrain: render a heightmap tessellated by its HAM tiles (build-ham's output) to
// an image (terrain/render_terrain.h), optionally with a JSON report of the triangles drawn.
#pragma once

#include <string>

#include "apps/run_splat_view.h"
#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct TerrainViewOptions {
  std::string heightmap;  // any heightmap build-ham reads
  std::string ham;        // build-ham's per-tile EXR
  std::string raw;        // "W,H,TYPE[,ENDIAN]" when the heightmap is RAW
  float tess_error_px = 2;
  float tess_distance_tiles = 3;  // d_max in tile diagonals
  bool wireframe = false;
};

// The camera (eye, target, up, view, fov, width, height), the background, the image and the
// report come from `view`; its input, turntable, path, occlusion, blend and shade do not apply. Throws
// Error(kUsage) for options that do not apply or bad values, Error(kBadInput) when the tiles do
// not match the heightmap (size, tile size), as the readers do otherwise, Error(kOutput).
StageSummary run_terrain_view(const SplatViewOptions& view, const TerrainViewOptions& terrain,
                              const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
