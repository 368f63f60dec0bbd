// splat-tile: declares the options of apps::run_splat_tile (lib/apps) and calls it.
#include "apps/run_splat_tile.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-tile",
      "Cut a survey (any number of point files of any format: LAS/LAZ tiles, PLY, .splk, '-') "
      "into square tiles in plan, for running the pipeline tile by tile on many machines: "
      "DIR/tiles/tile_<i>_<j>.splk holds the points with i*S <= x < (i+1)*S and "
      "j*S <= y < (j+1)*S, then a halo of the other tiles' points within H of that square "
      "(attribute halo: 0 own, 1 halo), and DIR/tiles.json lists the tiles, the halo and the "
      "inputs with their checksums. The grid is anchored at 0, so tiles of one size line up "
      "across runs. Inputs with a halo attribute (tiles of an earlier run) give their own points "
      "only. One input is held in memory at a time, then one tile.",
      "  $ splat-tile survey/*.laz -o tiled --tile-size 250\n"
      "  $ splat-tile scan.ply -o parts --tile-size 0.5 --halo 0.05 --report tile.json\n"
      "  $ splat-tile tiled/tiles/*.splk -o retiled --tile-size 500  # cut again, larger\n");
  splatkit::apps::SplatTileOptions o;
  auto& app = tool.app();
  app.add_option("IN", o.inputs, "Input files, any format ('-' = stdin, once)")->required();
  app.add_option("-o,--output", o.out_dir,
                 "Output folder (created; its tiles/ folder too): tiles/*.splk and tiles.json")
      ->required();
  app.add_option("--tile-size", o.tile_size, "Side S of the square tiles, in the inputs' units")
      ->required()
      ->check(splatkit::positive_finite());
  app.add_option("--halo", o.halo,
                 "Halo H: the other tiles' points within H of a tile's square (in plan) that it "
                 "also holds. Default: twice the 99th percentile, over the first input of 64 "
                 "points or more, of the "
                 "distance from a point to its 64th nearest (the widest neighbourhood "
                 "estimate-normals reads with its defaults reaches a row of 64 and each of their "
                 "rows of up to 32)")
      ->check(splatkit::finite_range(0, 1e300));
  app.add_flag("--morton-grid", o.morton_grid,
               "Anchor the grid at the survey's lower corner and make S the largest side of "
               "a Morton cell of the survey's bounding cube at most --tile-size, so that the "
               "tiles are columns of the cells build-spt's octree over the whole survey is made "
               "of and their .spt files merge into that build's list. Reads the inputs twice "
               "(not with '-')");
  tool.add_columns_option(o.read.columns);
  app.add_option("--report,--stats", o.report, "Write counts, timings and peak RSS as JSON here");
  tool.add_threads_option();
  return tool.run_stage(argc, argv, o.out_dir, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_splat_tile(o, progress);
  });
}
