// splat-convert: convert between point-cloud formats (PLY, XYZ/CSV, OFF, LAS, PCD -> PLY, XYZ,
// OFF, .splk), keeping every attribute.
#include "formats/provenance.h"
#include "formats/read_cloud.h"
#include "formats/write_cloud.h"
#include "splatkit/error.h"
#include "splatkit/progress.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool("splat-convert",
                      "Convert a point cloud between formats, keeping normals, radii, colours, "
                      "extra attributes and faces. The output format follows OUT's extension "
                      "(.ply .xyz .txt .csv .off .splk; '-' writes .splk to stdout).",
                      "  $ splat-convert scan.las scan.splk\n"
                      "  $ splat-convert --ascii model.splk model.ply\n"
                      "  $ cat points.xyz | splat-convert --columns x,y,z,nx,ny,nz - out.ply\n"
                      "  $ for f in scans/*.ply; do splat-convert -q \"$f\" \"out/$(basename "
                      "\"$f\" .ply).splk\"; done\n");
  std::string input, output, format;
  splatkit::ReadOptions read;
  splatkit::WriteOptions write;
  tool.app().add_option("IN", input, "Input file ('-' = stdin)")->required();
  tool.app()
      .add_option("OUT", output, "Output file ('-' = stdout, .splk unless --format)")
      ->required();
  tool.app().add_option("--columns", read.columns,
                        "Column layout of text input, e.g. x,y,z,nx,ny,nz,r,g,b ('_' skips)");
  tool.app()
      .add_option("--format", format, "Output format, overriding the extension")
      ->check(CLI::IsMember({"ply", "xyz", "off", "splk"}));
  auto* ascii = tool.app().add_flag("--ascii", write.ascii, "PLY: write ASCII");
  tool.app()
      .add_flag("--big-endian", write.big_endian, "PLY: write binary big-endian")
      ->excludes(ascii);
  return tool.run(argc, argv, [&] {
    splatkit::Progress progress(tool.name(), tool.quiet() || output == "-");
    if (format == "ply") write.format = splatkit::FileFormat::kPly;
    if (format == "xyz") write.format = splatkit::FileFormat::kXyz;
    if (format == "off") write.format = splatkit::FileFormat::kOff;
    if (format == "splk") write.format = splatkit::FileFormat::kSplk;
    splatkit::InputStream in(input);
    splatkit::LoadedCloud doc = splatkit::read_cloud(in, read);
    nlohmann::json options = {{"columns", read.columns}, {"format", format}};
    doc.metadata = splatkit::make_provenance(tool.name(), options, in, doc, doc.cloud);
    splatkit::write_cloud(doc, output, write);
    progress.finish(doc.cloud.size());
  });
}
