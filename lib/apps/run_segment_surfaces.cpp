#include "apps/run_segment_surfaces.h"

#include <utility>

#include "apps/robust_provenance.h"
#include "graph/drop_small_surfaces.h"
#include "graph/merge_coplanar_surfaces.h"
#include "graph/merge_small_surfaces.h"
#include "graph/refine_surface_borders.h"
#include "graph/segment_surfaces.h"
#include "graph/settle_plane_borders.h"
#include "graph/split_planar_surfaces.h"
#include "graph/split_small_faces.h"
#include "graph_io/chunks_to_attributes.h"
#include "graph_io/graph_chunks.h"
#include "splatkit/check_splats.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"

namespace splatkit::apps {

namespace {

using graph::Segmentation;

struct GraphChunks {
  graph::DecodedGraph graph;
  std::vector<graph::SplatClass> classes;
};

// Decodes GRPH and CLAS, and checks CLIP and SURF (passed on to OUT) by decoding them too.
GraphChunks decode_chunks(const LoadedCloud& doc, const std::string& name) {
  const RawChunk* grph =
      graph::find_single_chunk(doc, graph::kGraphChunkType, "neighbour graph", name);
  const RawChunk* clas =
      graph::find_single_chunk(doc, graph::kClassChunkType, "splat classes", name);
  const RawChunk* clip =
      graph::find_single_chunk(doc, graph::kClipChunkType, "clip partners", name);
  const RawChunk* surf =
      graph::find_single_chunk(doc, graph::kSurfaceChunkType, "surface ids", name);
  if (grph == nullptr) throw_bad_input(name, "no neighbour graph; run build-splat-graph first");
  if (clas == nullptr)
    throw_bad_input(name, "no splat classes (CLAS chunk); run build-splat-graph first");
  const uint64_t n = doc.cloud.size();
  GraphChunks out{graph::decode_graph_chunk(*grph, n, name),
                  graph::decode_class_chunk(*clas, n, name)};
  if (clip != nullptr) {
    const graph::ClipPartnerTable table = graph::decode_clip_chunk(*clip, n, name);
    try {
      table.check_consistent();
    } catch (const std::logic_error& e) {
      throw_bad_input(name, std::string("CLIP chunk: ") + e.what());
    }
  }
  if (surf != nullptr) graph::decode_surface_chunk(*surf, n, name);
  return out;
}

}  // namespace

StageSummary run_segment_surfaces(const SegmentSurfacesOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  const bool ply = lower_extension(output) == "ply";
  if (!is_stream_path(output) && !ply && lower_extension(output) != "splk")
    throw_usage("OUT must end in .splk or .ply, or be '-': " + output);
  if (o.method != "robust" && o.method != "components")
    throw_usage("--method must be robust or components, got '" + o.method + "'");
  if (o.min_size == 0) throw_usage("--min-size must be >= 1");
  if (o.merge_below == 0) throw_usage("--merge-below must be >= 1");
  if (!(o.coplanar_scales >= 0 && o.coplanar_scales <= 1000))
    throw_usage("--coplanar-scales must be in [0, 1000]");
  const std::optional<float>& core = o.robust.core_threshold;
  if (core && !(*core >= -1 && *core <= 1)) throw_usage("--core must be a number in [-1, 1]");
  if (o.robust.min_core_size == 0) throw_usage("--min-core must be >= 1");
  const bool robust = o.method == "robust";

  Stage stage("segment-surfaces", o.paths);
  LoadedCloud doc = stage.read({}, progress);
  const std::string& name = stage.input_name();
  check_splats(doc.cloud, name);
  const GraphChunks chunks =
      stage.phase("decode", "decoding the graph", [&] { return decode_chunks(doc, name); });
  graph::RobustSegmentOptions robust_options = o.robust;
  robust_options.sharp_threshold = chunks.graph.sharp_threshold;
  graph::RobustSegmentInfo chosen;
  const graph::DecodedGraph& g = chunks.graph;
  Segmentation seg = stage.phase("segment", "segmenting the surfaces", [&] {
    progress(0.0, "segmenting");
    return robust ? graph::segment_surfaces_robust(g.graph, g.edge_flags, graph::kEdgeSharp,
                                                   doc.cloud.positions, doc.cloud.normals,
                                                   robust_options, &chosen)
                  : graph::segment_surfaces(g.graph, g.edge_flags, graph::kEdgeSharp);
  });
  const uint32_t segments_segmented = seg.count();
  graph::RefineBordersInfo refined;
  seg = stage.phase("refine", "refining the borders", [&] {
    progress(0.0, "refining the borders");
    graph::RefineBordersOptions ro;
    ro.rounds = o.refine_rounds;
    ro.min_surface_size = o.merge_below;
    return graph::refine_surface_borders(g.graph, doc.cloud.positions, doc.cloud.normals,
                                         std::move(seg), ro, &refined);
  });
  uint32_t segments_before = 0;
  graph::CoplanarMergeInfo coplanar;
  uint32_t split = 0;
  uint64_t settled = 0;
  uint32_t faces = 0;
  seg = stage.phase("merge", "merging the fragments", [&] {
    Segmentation merged = graph::merge_small_surfaces(g.graph, std::move(seg), o.merge_below,
                                                      {doc.cloud.positions, doc.cloud.radii});
    graph::SplitPlanesOptions so;
    so.offset_scales = o.coplanar_scales;
    so.min_size = o.merge_below;
    merged = graph::split_planar_surfaces(g.graph, doc.cloud.positions, doc.cloud.normals,
                                          doc.cloud.radii, std::move(merged), so, &split);
    graph::SplitSmallFacesOptions fo;
    fo.offset_scales = o.coplanar_scales;
    merged = graph::split_small_faces(g.graph, doc.cloud.positions, doc.cloud.normals,
                                      doc.cloud.radii, std::move(merged), fo, &faces);
    graph::CoplanarMergeOptions co;
    co.offset_scales = o.coplanar_scales;
    co.min_size = o.merge_below;
    merged = graph::merge_coplanar_surfaces(g.graph, doc.cloud.positions, doc.cloud.normals,
                                            doc.cloud.radii, std::move(merged), co, &coplanar);
    graph::SettlePlaneBordersOptions sp;
    sp.offset_scales = o.coplanar_scales;
    sp.min_size = o.merge_below;
    merged = graph::settle_plane_borders(g.graph, doc.cloud.positions, doc.cloud.normals,
                                         doc.cloud.radii, std::move(merged), sp, &settled);
    segments_before = merged.count();
    return graph::drop_small_surfaces(std::move(merged), o.min_size);
  });
  nlohmann::json prov_options = {{"min_size", o.min_size},
                                 {"method", o.method},
                                 {"refine_rounds", o.refine_rounds},
                                 {"merge_below", o.merge_below},
                                 {"coplanar_scales", o.coplanar_scales}};
  if (robust) put_robust_options(prov_options, o.robust);
  stage.stamp(doc, prov_options, /*keep_chunks=*/true);
  const uint64_t n = doc.cloud.size();
  WriteOptions write;
  if (ply) {
    doc.cloud.set_extra(graph::surface_id_attribute(seg));
    doc.cloud.set_extra(graph::class_attribute(chunks.classes));
    write.format = FileFormat::kPly;
  } else {
    graph::put_chunk(doc, graph::encode_surface_chunk(seg));
    write.format = FileFormat::kSplk;
  }
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    uint64_t unassigned = 0;
    for (uint32_t id : seg.surface) unassigned += id == graph::kNoSurface;
    report = {{"splats", n},
              {"segments", seg.count()},
              {"segments_segmented", segments_segmented},
              {"segments_before_min_size", segments_before},
              {"unassigned_splats", unassigned},
              {"sizes", seg.sizes}};
    report["refine"] = {{"planes", refined.planes},       {"spheres", refined.spheres},
                        {"cylinders", refined.cylinders}, {"unexplained", refined.unexplained},
                        {"joined", refined.joined},       {"split", refined.split},
                        {"passes", refined.passes},       {"rounds", refined.rounds},
                        {"moved_splats", refined.moved}};
    report["coplanar"] = {{"planar", coplanar.planar},     {"joined", coplanar.joined},
                          {"disjoint", coplanar.disjoint}, {"split", split},
                          {"small_faces", faces},          {"settled_splats", settled}};
    if (robust) {
      report["normal_noise_degrees"] = chosen.normal_noise_degrees;
      report["sharp_edges_within_surfaces"] = chosen.sharp_edges_within;
      report["core_threshold"] = chosen.core_threshold;
    }
  }
  stage.write(doc, write, std::move(report));
  return {n, "splats", std::to_string(seg.count()) + " surfaces"};
}

}  // namespace splatkit::apps
