// build-splat-graph: the splat graph of seed 002 ch. 3–4 for a cloud of splats (normals and radii):
// neighbour graph, sharp edges, per-splat class, clip partners. The work is
// splatkit::graph::build_splat_graph (lib/graph); this file parses arguments, reads, writes the
// .splk chunks GRPH, CLAS and CLIP (lib/graph/graph/graph_chunks.h) and reports.
#include <nlohmann/json.hpp>

#include <string_view>

#include <chrono>

#include "common/robust_options.h"
#include "formats/provenance.h"
#include "formats/read_cloud.h"
#include "formats/splk.h"
#include "formats/write_cloud.h"
#include "graph/build_splat_graph.h"
#include "graph_io/graph_chunks.h"
#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/progress.h"
#include "splatkit/seconds_since.h"
#include "splatkit/tool.h"

namespace {

using splatkit::Clock;
using splatkit::seconds_since;

nlohmann::json stats_json(const splatkit::graph::SplatGraphStats& s) {
  return {{"splats", s.splats},
          {"edges", s.edges},
          {"mean_degree", s.mean_degree},
          {"sharp_edges", s.sharp_edges},
          {"real_intersections", s.crossing_edges},
          {"candidate_splats", s.candidate_splats},
          {"edge_splats", s.edge_splats},
          {"intersection_splats", s.intersection_splats},
          {"clipped_splats", s.clipped_splats},
          {"clip_partners", s.clip_partners},
          {"surfaces", s.surfaces},
          {"normal_noise_degrees", s.surface_method.normal_noise_degrees},
          {"core_threshold", s.surface_method.core_threshold}};
}

}  // namespace

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "build-splat-graph",
      "Build the splat graph of a cloud of splats with normals and radii (run estimate-normals "
      "first otherwise): neighbours whose bounding spheres overlap, sharp edges (n_i.n_j < W), "
      "the class of every splat (smooth, edge, intersection), disc-disc crossings and the clip "
      "partners with their rules. OUT is .splk ('-' = stdout) with the splats and the chunks "
      "GRPH (graph, CSR delta+varint), CLAS (classes) and CLIP (clip partners).",
      "  $ build-splat-graph part.splk part-graph.splk\n"
      "  $ build-splat-graph part.ply - --sharp 0.8 --report graph.json | segment-surfaces - "
      "parts.ply\n");
  std::string input, output, report_path;
  splatkit::graph::SplatGraphOptions options;
  auto& app = tool.app();
  app.add_option("IN", input, "Input splats with normals and radii, any format ('-' = stdin)")
      ->required();
  app.add_option("OUT", output, "Output .splk ('-' = stdout)")->required();
  app.add_option("--sharp", options.sharp_threshold,
                 "W: an edge is sharp when the normals' dot product is below W")
      ->default_val(0.9f)
      ->check(CLI::Range(-1.0f, 1.0f));
  app.add_option("--boundary-gap", options.boundary_gap_degrees,
                 "Angular gap (degrees) of the continuous neighbours that makes a splat an edge "
                 "(Linsen's test)")
      ->default_val(90.0)
      ->check(CLI::Range(1e-6, 360.0));
  std::string surfaces = "robust";
  app.add_option("--surfaces", surfaces,
                 "Surfaces that group the clip partners: robust (grow from core splats, see "
                 "segment-surfaces) or components (the seed's)")
      ->default_val("robust")
      ->check(CLI::IsMember({"robust", "components"}));
  splatkit::tools::add_robust_options(app, options.robust);
  app.add_option("--report", report_path, "Write the seed's table columns and timings as JSON");
  tool.add_threads_option();

  return tool.run(argc, argv, [&] {
    const Clock::time_point start = Clock::now();
    options.robust_surfaces = surfaces == "robust";
    if (output != "-" && !std::string_view(output).ends_with(".splk"))
      splatkit::throw_usage("OUT must end in .splk or be '-' (the graph chunks need .splk): " +
                            output);
    if (!report_path.empty() && report_path == output)
      splatkit::throw_usage("--report must not be OUT");

    splatkit::Progress progress(tool.name(), tool.quiet() || output == "-");
    Clock::time_point t0 = Clock::now();
    splatkit::InputStream in(input);
    splatkit::LoadedCloud doc = splatkit::read_cloud(in);
    const double read_s = seconds_since(t0);
    if (!doc.cloud.has_normals() || !doc.cloud.has_radii())
      splatkit::throw_bad_input(splatkit::display_name(input),
                                std::string("splats need normals and radii (missing: ") +
                                    (doc.cloud.has_normals() ? "radii" : "normals") +
                                    "); run estimate-normals first");

    t0 = Clock::now();
    const splatkit::graph::SplatGraph g =
        splatkit::graph::build_splat_graph(doc.cloud, options, progress.callback());
    const double graph_s = seconds_since(t0);

    t0 = Clock::now();
    // Chunks from an earlier run index the same splats but describe another graph.
    splatkit::drop_chunks_tied_to_splats(doc);
    splatkit::RawChunk grph =
        splatkit::graph::encode_graph_chunk(g.graph, g.edge_flags, options.sharp_threshold);
    const std::size_t graph_bytes = grph.payload.size();
    doc.chunks.push_back(std::move(grph));
    doc.chunks.push_back(splatkit::graph::encode_class_chunk(g.classes));
    doc.chunks.push_back(splatkit::graph::encode_clip_chunk(g.clip));
    nlohmann::json prov_options = {{"sharp", options.sharp_threshold},
                                   {"boundary_gap", options.boundary_gap_degrees},
                                   {"surfaces", surfaces}};
    if (options.robust_surfaces) splatkit::tools::put_robust_options(prov_options, options.robust);
    doc.metadata = splatkit::make_provenance(tool.name(), prov_options, in, doc, doc.cloud);
    splatkit::WriteOptions write;
    write.format = splatkit::FileFormat::kSplk;
    splatkit::write_cloud(doc, output, write);
    const double write_s = seconds_since(t0);

    if (!report_path.empty()) {
      nlohmann::json report = stats_json(g.stats);
      report["tool"] = tool.name();
      report["input"] = splatkit::display_name(input);
      report["output"] = splatkit::display_name(output, true);
      report["options"] = prov_options;
      report["threads"] = tool.threads();
      report["graph_chunk_bytes"] = graph_bytes;
      report["bytes_per_edge"] =
          g.stats.edges > 0 ? static_cast<double>(graph_bytes) / g.stats.edges : 0.0;
      report["time_s"] = graph_s;
      const splatkit::graph::SplatGraphTimings& t = g.timings;
      // "graph" is the whole of build_splat_graph; the four after it are its phases.
      report["timings_s"] = {{"read", read_s},         {"graph", graph_s},
                             {"overlaps", t.overlaps}, {"classify", t.classify},
                             {"surfaces", t.surfaces}, {"clip", t.clip},
                             {"write", write_s},       {"command", seconds_since(start)}};
      splatkit::OutputFile out(report_path);
      out.write(report.dump(2) + "\n");
      out.commit();
    }
    progress.finish(doc.cloud.size(), "splats",
                    std::to_string(g.stats.edges) + " edges, " +
                        std::to_string(g.stats.sharp_edges) + " sharp, " +
                        std::to_string(g.stats.clipped_splats) + " clipped");
  });
}
