// segment-surfaces: the smooth surfaces of a splat graph (SPEC §5, seed 002 §5.4): connected
// components over the continuous (non-sharp) edges of the GRPH chunk that build-splat-graph
// wrote, ids in the order of each surface's lowest splat index. The work is
// splatkit::graph::segment_surfaces; this file reads the chunks, writes SURF (or a PLY with
// surface_id and class per vertex) and reports.
#include <nlohmann/json.hpp>

#include <optional>
#include <string_view>
#include <utility>

#include <chrono>

#include "common/robust_options.h"
#include "formats/provenance.h"
#include "formats/read_cloud.h"
#include "formats/splk.h"
#include "formats/write_cloud.h"
#include "graph/build_splat_graph.h"
#include "graph_io/graph_chunks.h"
#include "graph/segment_surfaces.h"
#include "graph/segment_surfaces_robust.h"
#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/progress.h"
#include "splatkit/seconds_since.h"
#include "splatkit/tool.h"

namespace {

using splatkit::Clock;
using splatkit::seconds_since;
using splatkit::graph::Segmentation;

// Surfaces with fewer than min_size splats lose their id (kNoSurface); the others are numbered
// again 0.. in the same order (lowest splat index), so ids stay deterministic and dense.
Segmentation drop_small_surfaces(Segmentation seg, uint32_t min_size) {
  if (min_size <= 1) return seg;  // every surface has a splat
  std::vector<uint32_t> new_id(seg.count(), splatkit::graph::kNoSurface);
  Segmentation out;
  for (uint32_t s = 0; s < seg.count(); ++s)
    if (seg.sizes[s] >= min_size) {
      new_id[s] = out.count();
      out.sizes.push_back(seg.sizes[s]);
    }
  out.surface.reserve(seg.surface.size());
  for (uint32_t id : seg.surface) out.surface.push_back(new_id[id]);
  return out;
}

void add_extra(splatkit::SplatCloud& cloud, const std::string& name, splatkit::ScalarType type,
               std::vector<double> values) {
  if (splatkit::ExtraAttribute* old = cloud.find_extra(name)) {
    old->type = type;
    old->values = std::move(values);
    return;
  }
  cloud.extras.push_back({name, type, std::move(values)});
}

}  // namespace

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "segment-surfaces",
      "Split the splats into smooth surfaces over the continuous edges of the neighbour graph "
      "that build-splat-graph stored in IN (GRPH and CLAS chunks). --method robust (default): "
      "surfaces grow from core splats (every continuous neighbour's normal within the core "
      "angle: half the sharp angle when the normals are noisy) so noisy creases do not merge "
      "faces; on clean normals it gives the components. --method "
      "components: the seed's connected components of the continuous edges. Ids "
      "are numbered in the order of each surface's lowest splat index, so they are the same on "
      "every run. OUT .splk ('-' = stdout) adds the SURF chunk; OUT .ply writes a binary PLY "
      "with the extra vertex properties surface_id (uint32) and class (uint8: 0 smooth, 1 edge, "
      "2 intersection). --min-size N: surfaces with fewer than N splats get no id "
      "(surface_id 4294967295 = 0xFFFFFFFF) and the remaining ones are numbered again 0.. in "
      "the same order; they are not merged into a neighbour.",
      "  $ segment-surfaces part-graph.splk part-surf.splk --report surfaces.json\n"
      "  $ segment-surfaces part-graph.splk part-surf.ply --min-size 50\n");
  std::string input, output, report_path;
  uint32_t min_size = 1;
  std::string method = "robust";
  splatkit::graph::RobustSegmentOptions robust;
  auto& app = tool.app();
  app.add_option("IN", input, "Input .splk from build-splat-graph ('-' = stdin)")->required();
  app.add_option("OUT", output, "Output .splk or .ply ('-' = .splk on stdout)")->required();
  app.add_option("--min-size", min_size,
                 "Surfaces with fewer splats get id 0xFFFFFFFF (no surface); not merged")
      ->default_val(1)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
  app.add_option("--method", method, "robust (grow from core splats) or components (the seed's)")
      ->default_val("robust")
      ->check(CLI::IsMember({"robust", "components"}));
  splatkit::tools::add_robust_options(app, robust);
  app.add_option("--report", report_path, "Write the surfaces and their sizes as JSON here");

  return tool.run(argc, argv, [&] {
    const Clock::time_point start = Clock::now();
    const bool ply = std::string_view(output).ends_with(".ply");
    if (output != "-" && !ply && !std::string_view(output).ends_with(".splk"))
      splatkit::throw_usage("OUT must end in .splk or .ply, or be '-': " + output);
    if (!report_path.empty() && report_path == output)
      splatkit::throw_usage("--report must not be OUT");

    splatkit::Progress progress(tool.name(), tool.quiet() || output == "-");
    Clock::time_point t0 = Clock::now();
    splatkit::InputStream in(input);
    splatkit::LoadedCloud doc = splatkit::read_cloud(in);
    const double read_s = seconds_since(t0);
    const std::string name = splatkit::display_name(input);
    const splatkit::RawChunk* grph =
        splatkit::graph::find_chunk(doc, splatkit::graph::kGraphChunkType);
    const splatkit::RawChunk* clas =
        splatkit::graph::find_chunk(doc, splatkit::graph::kClassChunkType);
    if (grph == nullptr)
      splatkit::throw_bad_input(name, "no neighbour graph; run build-splat-graph first");
    if (clas == nullptr)
      splatkit::throw_bad_input(name, "no splat classes (CLAS chunk); run build-splat-graph first");
    const uint64_t n = doc.cloud.size();
    t0 = Clock::now();
    const splatkit::graph::DecodedGraph graph = splatkit::graph::decode_graph_chunk(*grph, n, name);
    const std::vector<splatkit::graph::SplatClass> classes =
        splatkit::graph::decode_class_chunk(*clas, n, name);

    const double decode_s = seconds_since(t0);
    t0 = Clock::now();
    if (method == "robust" && !doc.cloud.has_normals())
      splatkit::throw_bad_input(name, "--method robust needs the splats' normals");
    robust.sharp_threshold = graph.sharp_threshold;
    splatkit::graph::RobustSegmentInfo chosen;
    Segmentation all = method == "robust"
                           ? splatkit::graph::segment_surfaces_robust(
                                 graph.graph, graph.edge_flags, splatkit::graph::kEdgeSharp,
                                 doc.cloud.positions, doc.cloud.normals, robust, &chosen)
                           : splatkit::graph::segment_surfaces(graph.graph, graph.edge_flags,
                                                               splatkit::graph::kEdgeSharp);
    const Segmentation seg = drop_small_surfaces(std::move(all), min_size);
    const double segment_s = seconds_since(t0);

    nlohmann::json prov_options = {{"min_size", min_size}, {"method", method}};
    if (method == "robust") splatkit::tools::put_robust_options(prov_options, robust);
    doc.metadata = splatkit::make_provenance(tool.name(), prov_options, in, doc, doc.cloud);
    splatkit::WriteOptions write;
    if (ply) {
      add_extra(doc.cloud, "surface_id", splatkit::ScalarType::kUInt32,
                std::vector<double>(seg.surface.begin(), seg.surface.end()));
      std::vector<double> class_values(n);
      for (uint64_t i = 0; i < n; ++i) class_values[i] = static_cast<double>(classes[i]);
      add_extra(doc.cloud, "class", splatkit::ScalarType::kUInt8, std::move(class_values));
      write.format = splatkit::FileFormat::kPly;
    } else {
      splatkit::graph::put_chunk(doc, splatkit::graph::encode_surface_chunk(seg));
      write.format = splatkit::FileFormat::kSplk;
    }
    t0 = Clock::now();
    splatkit::write_cloud(doc, output, write);
    const double write_s = seconds_since(t0);

    if (!report_path.empty()) {
      uint64_t unassigned = 0;
      for (uint32_t id : seg.surface) unassigned += id == splatkit::graph::kNoSurface;
      nlohmann::json report = {{"tool", tool.name()},
                               {"input", name},
                               {"output", splatkit::display_name(output, true)},
                               {"options", prov_options},
                               {"splats", n},
                               {"segments", seg.count()},
                               {"segments_before_min_size", all.count()},
                               {"unassigned_splats", unassigned},
                               {"sizes", seg.sizes},
                               {"timings_s",
                                {{"read", read_s},
                                 {"decode", decode_s},
                                 {"segment", segment_s},
                                 {"write", write_s},
                                 {"command", seconds_since(start)}}}};
      if (method == "robust") {
        report["normal_noise_degrees"] = chosen.normal_noise_degrees;
        report["core_threshold"] = chosen.core_threshold;
      }
      splatkit::OutputFile out(report_path);
      out.write(report.dump(2) + "\n");
      out.commit();
    }
    progress.finish(n, "splats", std::to_string(seg.count()) + " surfaces");
  });
}
