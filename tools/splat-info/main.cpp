// splat-info: declares the options of apps::run_splat_info (lib/apps) and calls it.
#include <iostream>

#include "apps/run_splat_info.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-info",
      "Describe point clouds (PLY, XYZ, LAS, LAZ, PCD, OFF, .splk), QSplat .qs and Sequential "
      "Point Tree .spt files, heightmaps (.tif .png .exr .hgt) and build-ham's tile EXRs, every "
      "kind with the same first lines: File, Format, Bytes, Points (a cloud's points, a "
      "heightmap's samples) or Entries (.qs nodes, .spt entries, tiles), Bounds (in the file's "
      "coordinates) and CRS; then the kind's own facts (attributes with ranges, header, .splk "
      "chunks and metadata; levels and leaves; quantisation; size, sample type, no-data and "
      "georeferencing; tiles, heights and HAM). --json gives the same facts with the keys file, "
      "format, bytes, points or entries, bounds and crs for every kind. A file that cannot be "
      "read is reported on stderr and the others are still described (exit code of the first "
      "failure).",
      "  $ splat-info scan.ply\n"
      "  $ splat-info --json model.splk | jq .points\n"
      "  $ estimate-normals scan.las - | splat-info -\n"
      "  $ splat-info --columns x,y,z,_,r,g,b points.txt\n");
  splatkit::apps::SplatInfoOptions o;
  auto& app = tool.app();
  app.add_option("FILE", o.files, "Files to describe ('-' = stdin)")->required();
  app.add_flag("--json", o.json, "Print a JSON report (an array when several files are given)");
  tool.add_columns_option(o.read.columns);
  return tool.run(argc, argv, [&] { splatkit::apps::run_splat_info(o, std::cout, std::cerr); });
}
