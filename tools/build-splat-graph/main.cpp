// build-splat-graph: declares the options of apps::run_build_splat_graph (lib/apps) and calls it.
#include "apps/run_build_splat_graph.h"
#include "common/robust_options.h"
#include "splatkit/tool.h"

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
  splatkit::apps::BuildSplatGraphOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input splats with normals and radii, any format ('-' = stdin)",
                  "Output .splk ('-' = stdout)");
  app.add_option("--sharp", o.graph.sharp_threshold,
                 "W: an edge is sharp when the normals' dot product is below W")
      ->default_val(0.9f)
      ->check(splatkit::finite_range(-1.0, 1.0));
  app.add_option("--boundary-gap", o.graph.boundary_gap_degrees,
                 "Angular gap (degrees) of the continuous neighbours that makes a splat an edge "
                 "(Linsen's test)")
      ->default_val(90.0)
      ->check(splatkit::finite_range(1e-6, 360.0));
  app.add_option("--surfaces", o.surfaces,
                 "Surfaces that group the clip partners: robust (grow from core splats, see "
                 "segment-surfaces) or components (connected components of the continuous edges)")
      ->default_val("robust")
      ->check(CLI::IsMember({"robust", "components"}));
  splatkit::tools::add_robust_options(app, o.graph.robust);
  app.add_option("--report,--stats", o.paths.report,
                 "Write the graph's counts (splats, edges, sharp edges, classes, clip partners) "
                 "and timings as JSON");
  tool.add_threads_option();
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_build_splat_graph(o, progress);
  });
}
