// splat-tile's work, callable without the command line: cut the points of any number of inputs
// into square tiles in plan, each written with a halo of its neighbours' points, so that the
// pipeline can run tile by tile (on many machines) and still see every point's neighbourhood.
//
// Output, in `out_dir` (created when missing, with its parent existing):
//   tiles/tile_<i>_<j>.splk  one per tile holding points: the tile's own points, then its halo
//                            points, with a uint8 attribute `halo` (0 own, 1 halo) and every
//                            field the inputs share; metadata "tile" says its square and counts;
//   tiles.json               the tile size, the halo and how it was chosen, the tiles (name,
//                            file, i, j, square, own and halo points) and the inputs (name,
//                            format, bytes, crc32c, points). Written last: its presence marks a
//                            complete run.
// Tile files of an earlier run that this run does not write are removed (only names
// tile_*.splk in tiles/). Every file is written to a temporary name and renamed, so a failure
// leaves no partial file; the parts kept between the two passes go to a temporary directory in
// out_dir, removed at the end.
// Memory: one input at a time, then one tile at a time (its points and halo).
// Inputs that carry a `halo` attribute (tiles of an earlier splat-tile run) give their own points
// only: tiles can be cut again at another size.
#pragma once

#include <string>
#include <vector>

#include "apps/stage_types.h"
#include "formats/read_cloud.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct SplatTileOptions {
  std::vector<std::string> inputs;  // any format read_cloud reads; at most one "-"
  std::string out_dir;
  double tile_size = 0;  // > 0, in the inputs' units
  double halo = -1;      // >= 0; negative: tile_halo() of the first input of 64 points or more
  // --morton-grid: the grid anchored at the survey box's lower corner, its side the largest
  // Morton cell side of the box's cube at most tile_size (apps/morton_tile_grid.h), so that
  // build-spt's tiles merge into the whole survey's list; the inputs are read twice (no "-").
  bool morton_grid = false;
  ReadOptions read;    // read.columns: text inputs' column layout
  std::string report;  // JSON report; empty = none; "-" = standard output
};

// Throws Error(kUsage) for bad options (no inputs, a size that is not positive and finite, "-"
// twice, a report inside the tile folder), Error(kBadInput) for an input that cannot be read or
// whose fields differ from the first input's, Error(kOutput) when out_dir or a file in it cannot
// be written, Error(kOutOfMemory).
StageSummary run_splat_tile(const SplatTileOptions& options,
                            const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
