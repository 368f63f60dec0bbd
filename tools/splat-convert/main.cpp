// splat-convert: declares the options of apps::run_splat_convert (lib/apps) and calls it.
#include "apps/run_splat_convert.h"
#include "splatkit/tool.h"

#include <string>
#include <vector>

int main(int argc, char** argv) {
  splatkit::Tool tool("splat-convert",
                      "Convert a point cloud between formats, keeping the normals, radii, "
                      "colours, extra attributes and faces that the output format holds (.splk "
                      "holds them all; formats/*.md say what the others keep; in PLY and XYZ, "
                      "segment-surfaces' surface ids and build-splat-graph's splat classes become "
                      "the attributes surface_id and class unless the cloud has attributes of "
                      "those names; the summary line names what OUT's format does not keep). The "
                      "output format follows OUT's "
                      "extension (.ply .xyz .txt .pts .csv .off .las .laz .splk, any case; another "
                      "is refused unless --format is given; '-' writes .splk to stdout).",
                      "  $ splat-convert scan.las scan.splk\n"
                      "  $ splat-convert tiled/tiles/*.splk survey.splk  # tiles' own points, "
                      "one cloud\n"
                      "  $ splat-convert surfaces/*.splk survey.splk  # segmented tiles, their "
                      "surfaces joined\n"
                      "  $ splat-convert scan.laz scan.las\n"
                      "  $ splat-convert --las-format 7 scan.ply scan.laz\n"
                      "  $ splat-convert --ascii model.splk model.ply\n"
                      "  $ cat points.xyz | splat-convert --columns x,y,z,nx,ny,nz - out.ply\n"
                      "  $ for f in scans/*.ply; do splat-convert -q \"$f\" \"out/$(basename "
                      "\"$f\" .ply).splk\"; done\n");
  splatkit::apps::SplatConvertOptions o;
  auto& app = tool.app();
  std::vector<std::string> files;  // IN... OUT
  app.add_option("IN... OUT", files,
                 "Input files ('-' = stdin), then the output file ('-' = stdout, .splk unless "
                 "--format). With several inputs their points are concatenated (points only; "
                 "the inputs must hold the same fields) and splat-tile's tiles give their own "
                 "points only (halo attribute 0), without the attribute; when every input holds "
                 "surface ids (segment-surfaces per tile), a tile's surface and its neighbour's "
                 "join where the halo points of each lie mostly on the other, and OUT gets one "
                 "set of ids (and the splat classes when every input has them)")
      ->required()
      ->expected(2, -1);
  app.callback([&] {
    o.paths.input = files.front();
    o.paths.output = files.back();
    o.more_inputs.assign(files.begin() + 1, files.end() - 1);
  });
  tool.add_columns_option(o.read.columns);
  app.add_option("--format", o.format, "Output format, overriding the extension")
      ->check(CLI::IsMember({"ply", "xyz", "off", "splk", "las", "laz"}));
  app.add_option("--las-format", o.write.las_format,
                 "LAS/LAZ output: point data format 0-3 (LAS 1.2) or 6-8 (LAS 1.4; LAZ with "
                 "LASzip's layered compressor). Default: the input's when it is LAS/LAZ of format "
                 "6-8, else 0-3 by the fields the cloud has (colours, GPS time)")
      ->check(CLI::IsMember({0, 1, 2, 3, 6, 7, 8}));
  tool.add_ply_encoding_options(o.write.ascii, o.write.big_endian);
  tool.add_threads_option();  // LAZ chunks are decoded in parallel
  app.add_option("--report,--stats", o.paths.report,
                 "Write the counts (points in and out, per input), the timings (read, write) and "
                 "peak RSS as JSON");
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_splat_convert(o, progress);
  });
}
