#include "apps/run_build_splat_graph.h"

#include <string_view>
#include <utility>

#include "apps/robust_provenance.h"
#include "graph_io/graph_chunks.h"
#include "splatkit/check_splats.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"

namespace splatkit::apps {

namespace {

nlohmann::json stats_json(const graph::SplatGraphStats& s) {
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
          {"sharp_edges_within_surfaces", s.surface_method.sharp_edges_within},
          {"core_threshold", s.surface_method.core_threshold}};
}

graph::SplatGraphOptions graph_options(const BuildSplatGraphOptions& o) {
  graph::SplatGraphOptions g = o.graph;
  g.keep_surface_ids = false;  // not written here: the surface ids are segment-surfaces' output
  if (o.surfaces != "robust" && o.surfaces != "components")
    throw_usage("--surfaces must be robust or components, got '" + o.surfaces + "'");
  g.robust_surfaces = o.surfaces == "robust";
  if (!(g.sharp_threshold >= -1 && g.sharp_threshold <= 1))
    throw_usage("--sharp must be a number in [-1, 1]");
  if (!(g.boundary_gap_degrees > 0 && g.boundary_gap_degrees <= 360))
    throw_usage("--boundary-gap must be a number of degrees in (0, 360]");
  const std::optional<float>& core = g.robust.core_threshold;
  if (core && !(*core >= -1 && *core <= 1)) throw_usage("--core must be a number in [-1, 1]");
  return g;
}

}  // namespace

StageSummary run_build_splat_graph(const BuildSplatGraphOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "splk")
    throw_usage("OUT must end in .splk or be '-' (the graph chunks need .splk): " + output);
  const graph::SplatGraphOptions options = graph_options(o);
  Stage stage("build-splat-graph", o.paths);
  LoadedCloud doc = stage.read({}, progress);
  check_splats(doc.cloud, stage.input_name());
  graph::SplatGraph g = stage.phase("graph", "building the splat graph", [&] {
    return graph::build_splat_graph_in_place(doc.cloud, options, progress);
  });

  nlohmann::json prov_options = {{"sharp", options.sharp_threshold},
                                 {"boundary_gap", options.boundary_gap_degrees},
                                 {"surfaces", o.surfaces}};
  if (options.robust_surfaces) put_robust_options(prov_options, options.robust);
  stage.stamp(doc, prov_options);
  std::size_t graph_bytes = 0;
  stage.phase("encode", "encoding the graph chunks", [&] {
    // The small chunks first, and what is done with freed, so that the graph's chunk (the bulk)
    // is coded with as little else held as possible; it consumes the rows as it codes them.
    RawChunk clas = graph::encode_class_chunk(g.classes);
    RawChunk clip = graph::encode_clip_chunk(g.clip);
    g.classes = {};
    g.clip = {};
    g.surfaces = {};
    RawChunk grph = graph::encode_graph_chunk(std::move(g.graph), std::move(g.edge_flags),
                                              options.sharp_threshold);
    graph_bytes = grph.payload.size();
    doc.chunks.push_back(std::move(grph));
    doc.chunks.push_back(std::move(clas));
    doc.chunks.push_back(std::move(clip));
  });
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    report = stats_json(g.stats);
    report["graph_chunk_bytes"] = graph_bytes;
    report["bytes_per_edge"] =
        g.stats.edges > 0 ? static_cast<double>(graph_bytes) / g.stats.edges : 0.0;
    const graph::SplatGraphTimings& t = g.timings;
    report["time_s"] = stage.seconds("graph");
    // "graph" is the whole of build_splat_graph; these are its phases.
    report["timings_s"] = {{"overlaps", t.overlaps},
                           {"classify", t.classify},
                           {"surfaces", t.surfaces},
                           {"clip", t.clip}};
  }
  stage.write(doc, WriteOptions{FileFormat::kSplk, false, false}, std::move(report));
  return {doc.cloud.size(), "splats",
          std::to_string(g.stats.edges) + " edges, " + std::to_string(g.stats.sharp_edges) +
              " sharp, " + std::to_string(g.stats.clipped_splats) + " clipped"};
}

}  // namespace splatkit::apps
