#include "apps/run_splat_convert.h"

#include "formats/write_cloud.h"
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
  const FileFormat f = write.format != FileFormat::kUnknown ? write.format
                       : o.paths.output == "-"              ? FileFormat::kSplk
                                                            : format_of_extension(o.paths.output);
  if (f == FileFormat::kUnknown)
    throw_usage("OUT's extension names no format (.ply, .splk, .xyz, .txt, .pts, .csv, .off, "
                ".las, .laz), and no --format is given: " +
                o.paths.output);
  if (write.ascii && write.big_endian) throw_usage("--ascii and --big-endian are alternatives");
  // Options for another format than the one written would be ignored: said instead.
  if ((write.ascii || write.big_endian) && f != FileFormat::kPly)
    throw_usage(std::string(write.ascii ? "--ascii" : "--big-endian") +
                " is for PLY output; OUT is " + std::string(format_name(f)));
  if (write.las_format >= 0 && f != FileFormat::kLas && f != FileFormat::kLaz)
    throw_usage("--las-format is for LAS or LAZ output; OUT is " + std::string(format_name(f)));
  Stage stage("splat-convert", o.paths);
  stage.check_output_format(write);
  progress(0.0, "reading");
  LoadedCloud doc = stage.read(o.read, progress);
  stage.stamp(doc, {{"columns", o.read.columns}, {"format", o.format}}, /*keep_chunks=*/true);
  write.format = f;
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
