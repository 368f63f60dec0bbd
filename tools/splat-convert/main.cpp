// splat-convert: declares the options of apps::run_splat_convert (lib/apps) and calls it.
#include "apps/run_splat_convert.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool("splat-convert",
                      "Convert a point cloud between formats, keeping normals, radii, colours, "
                      "extra attributes and faces. The output format follows OUT's extension "
                      "(.ply .xyz .txt .csv .off .las .laz .splk; '-' writes .splk to stdout).",
                      "  $ splat-convert scan.las scan.splk\n"
                      "  $ splat-convert scan.laz scan.las\n"
                      "  $ splat-convert --ascii model.splk model.ply\n"
                      "  $ cat points.xyz | splat-convert --columns x,y,z,nx,ny,nz - out.ply\n"
                      "  $ for f in scans/*.ply; do splat-convert -q \"$f\" \"out/$(basename "
                      "\"$f\" .ply).splk\"; done\n");
  splatkit::apps::SplatConvertOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input file ('-' = stdin)",
                  "Output file ('-' = stdout, .splk unless --format)");
  tool.add_columns_option(o.read.columns);
  app.add_option("--format", o.format, "Output format, overriding the extension")
      ->check(CLI::IsMember({"ply", "xyz", "off", "splk", "las", "laz"}));
  tool.add_ply_encoding_options(o.write.ascii, o.write.big_endian);
  tool.add_threads_option();  // LAZ chunks are decoded in parallel
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_splat_convert(o, progress);
  });
}
