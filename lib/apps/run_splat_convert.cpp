#include "apps/run_splat_convert.h"

#include "formats/write_cloud.h"
#include "graph_io/chunks_to_attributes.h"
#include "splatkit/error.h"

namespace splatkit::apps {

namespace {

FileFormat format_option(const std::string& format) {
  if (format.empty()) return FileFormat::kUnknown;
  if (format == "ply") return FileFormat::kPly;
  if (format == "xyz") return FileFormat::kXyz;
  if (format == "off") return FileFormat::kOff;
  if (format == "splk") return FileFormat::kSplk;
  if (format == "las") return FileFormat::kLas;
  if (format == "laz") return FileFormat::kLaz;
  throw_usage("--format must be ply, xyz, off, splk, las or laz, got '" + format + "'");
}

}  // namespace

StageSummary run_splat_convert(const SplatConvertOptions& o, const ProgressFn& progress) {
  WriteOptions write = o.write;
  write.format = format_option(o.format);
  Stage stage("splat-convert", o.paths);
  const FileFormat f = stage.check_output_format(write);
  progress(0.0, "reading");
  LoadedCloud doc = stage.read(o.read, progress);
  stage.stamp(doc, {{"columns", o.read.columns}, {"format", o.format}}, /*keep_chunks=*/true);
  write.format = f;
  // Surface ids and splat classes become attributes where the format keeps attributes but not
  // chunks (LAS and OFF keep neither: there the chunks are only reported dropped).
  if (f == FileFormat::kPly || f == FileFormat::kXyz)
    graph::chunks_to_attributes(doc, stage.input_name());
  stage.write(doc, write);
  // What the output format cannot hold, said in the summary line (not an error: converting to a
  // plainer format is often the point).
  std::string lost;
  for (const std::string& what : fields_not_written(doc, f, write))
    lost += (lost.empty() ? "" : ", ") + what;
  return {doc.cloud.size(), "points",
          lost.empty() ? "" : std::string(format_name(f)) + " does not keep " + lost};
}

}  // namespace splatkit::apps
