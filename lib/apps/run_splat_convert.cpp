#include "apps/run_splat_convert.h"

#include "formats/provenance.h"
#include "formats/write_cloud.h"
#include "graph/join_tile_surfaces.h"
#include "graph_io/chunks_to_attributes.h"
#include "graph_io/graph_chunks.h"
#include "splatkit/append_points.h"
#include "splatkit/error.h"
#include "splatkit/same_file.h"
#include "splatkit/take_own_points.h"

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

// An input's record in the metadata's list of inputs, with the points it gave.
nlohmann::json input_json(const InputStream& in, const std::string& format, std::size_t points) {
  nlohmann::json r = input_record(in, format);
  r["points"] = points;
  return r;
}

// Tiles of segment-surfaces (SURF chunks): their surfaces joined across the halos
// (graph/join_tile_surfaces.h), and their splat classes (CLAS) when every tile has them.
struct TileSurfaces {
  bool all = true;          // every input so far had a SURF chunk
  bool classes = true;      // and a CLAS chunk
  graph::TileSurfaceJoin join;
  std::vector<graph::SplatClass> own_classes;

  void add(const LoadedCloud& in, std::span<const uint32_t> own, const std::string& name) {
    if (!all) return;
    const RawChunk* surf =
        graph::find_single_chunk(in, graph::kSurfaceChunkType, "surface ids", name);
    if (surf == nullptr) {
      all = false;
      return;
    }
    const uint64_t n = in.cloud.size();
    const graph::Segmentation seg = graph::decode_surface_chunk(*surf, n, name);
    join.add_tile(in.cloud.origin, in.cloud.positions, own, seg.surface, seg.count());
    const RawChunk* clas =
        graph::find_single_chunk(in, graph::kClassChunkType, "splat classes", name);
    classes = classes && clas != nullptr;
    if (!classes) return;
    const std::vector<graph::SplatClass> c = graph::decode_class_chunk(*clas, n, name);
    for (const uint32_t i : own) own_classes.push_back(c[i]);
  }
};

// The inputs' own points concatenated into `doc` (the first input's, read by the stage), in the
// first input's frame; returns the inputs' names, sizes and checksums. With surface ids in every
// input, `surfaces` gets them joined.
nlohmann::json concatenate(Stage& stage, LoadedCloud& doc, const SplatConvertOptions& o,
                           const ProgressFn& progress, TileSurfaces& surfaces) {
  std::vector<uint32_t> keep = take_own_points(doc.cloud);
  surfaces.add(doc, keep, stage.input_name());
  SplatCloud all;
  all.origin = doc.cloud.origin;
  append_points(all, doc.cloud, keep, stage.input_name());
  nlohmann::json inputs = nlohmann::json::array();
  inputs.push_back(input_json(stage.input(), doc.format, keep.size()));
  const double count = static_cast<double>(o.more_inputs.size() + 1);
  for (std::size_t a = 0; a < o.more_inputs.size(); ++a) {
    InputStream in(o.more_inputs[a]);
    LoadedCloud more = stage.phase("read", "reading " + in.name(), [&] {
      return read_cloud(in, o.read, [&](double f, const char* phase) {
        if (f >= 0) progress((static_cast<double>(a + 1) + f) / count, phase);
      });
    });
    keep = take_own_points(more.cloud);
    surfaces.add(more, keep, in.name());
    append_points(all, more.cloud, keep, in.name());  // refuses other fields, naming the input
    inputs.push_back(input_json(in, more.format, keep.size()));
  }
  doc.cloud = std::move(all);
  doc.chunks.clear();
  return inputs;
}

}  // namespace

StageSummary run_splat_convert(const SplatConvertOptions& o, const ProgressFn& progress) {
  WriteOptions write = o.write;
  write.format = format_option(o.format);
  Stage stage("splat-convert", o.paths);
  const FileFormat f = stage.check_output_format(write);
  progress(0.0, "reading");
  for (const std::string& in : o.more_inputs) {
    if (in == "-" && o.paths.input == "-") throw_usage("standard input ('-') given twice");
    if (same_file(in, o.paths.output, 0, 1))
      throw_usage("OUT is the input file " + in + " (an input is never overwritten)");
    if (!o.paths.report.empty() && same_file(in, o.paths.report, 0, 1))
      throw_usage("--report must not be the input file " + in);
  }
  LoadedCloud doc = stage.read(o.read, progress);
  const bool many = !o.more_inputs.empty();
  nlohmann::json inputs;
  TileSurfaces surfaces;
  if (many) inputs = concatenate(stage, doc, o, progress, surfaces);
  stage.stamp(doc, {{"columns", o.read.columns}, {"format", o.format}}, /*keep_chunks=*/!many);
  if (many) doc.metadata["inputs"] = inputs;
  nlohmann::json joined;
  if (many && surfaces.all) {  // the tiles' surfaces, one set of ids
    graph::TileJoinInfo info;
    const graph::Segmentation seg = stage.phase("join_surfaces", "joining the surfaces",
                                                [&] { return surfaces.join.finish(&info); });
    graph::put_chunk(doc, graph::encode_surface_chunk(seg));
    if (surfaces.classes) graph::put_chunk(doc, graph::encode_class_chunk(surfaces.own_classes));
    joined = {{"surfaces", seg.count()},
              {"tile_surfaces", info.tile_surfaces},
              {"joins", info.joins},
              {"halo_points", info.halo_points},
              {"halo_points_matched", info.matched}};
  }
  write.format = f;
  // Surface ids and splat classes become attributes where the format keeps attributes but not
  // chunks (LAS and OFF keep neither: there the chunks are only reported dropped).
  if (f == FileFormat::kPly || f == FileFormat::kXyz)
    graph::chunks_to_attributes(doc, stage.input_name());
  nlohmann::json report = {{"points", doc.cloud.size()}, {"output_format", format_name(f)}};
  if (many) report["inputs"] = inputs;
  if (!joined.is_null()) report["surfaces"] = joined;
  stage.write(doc, write, report);
  // What the output format cannot hold, said in the summary line (not an error: converting to a
  // plainer format is often the point).
  std::string lost;
  for (const std::string& what : fields_not_written(doc, f, write))
    lost += (lost.empty() ? "" : ", ") + what;
  std::string extra =
      joined.is_null() ? ""
                       : std::to_string(joined["surfaces"].get<uint32_t>()) + " surfaces (" +
                             std::to_string(joined["tile_surfaces"].get<uint32_t>()) +
                             " in the tiles, joined across their halos)";
  if (!lost.empty())
    extra += (extra.empty() ? "" : "; ") + std::string(format_name(f)) + " does not keep " + lost;
  return {doc.cloud.size(), "points", extra};
}

}  // namespace splatkit::apps
