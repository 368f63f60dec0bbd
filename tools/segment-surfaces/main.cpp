// segment-surfaces: declares the options of apps::run_segment_surfaces (lib/apps) and calls it.
#include "apps/run_segment_surfaces.h"
#include "common/robust_options.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "segment-surfaces",
      "Split the splats into smooth surfaces over the continuous edges of the neighbour graph "
      "that build-splat-graph stored in IN (GRPH and CLAS chunks). --method robust (default): "
      "surfaces grow from core splats (every continuous neighbour's normal within the core "
      "angle: half the sharp angle when the normals are noisy) so noisy creases do not merge "
      "faces; on clean normals it gives the components. --method "
      "components: the connected components of the continuous edges. Ids "
      "are numbered in the order of each surface's lowest splat index, so they are the same on "
      "every run. OUT .splk ('-' = stdout) adds the SURF chunk; OUT .ply writes a binary PLY "
      "with the extra vertex properties surface_id (uint32) and class (uint8: 0 smooth, 1 edge, "
      "2 intersection). --min-size N: surfaces with fewer than N splats get no id "
      "(surface_id 4294967295 = 0xFFFFFFFF) and the remaining ones are numbered again 0.. in "
      "the same order; they are not merged into a neighbour.",
      "  $ segment-surfaces part-graph.splk part-surf.splk --report surfaces.json\n"
      "  $ segment-surfaces part-graph.splk part-surf.ply --min-size 50\n");
  splatkit::apps::SegmentSurfacesOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input .splk from build-splat-graph ('-' = stdin)",
                  "Output .splk or .ply ('-' = .splk on stdout)");
  app.add_option("--min-size", o.min_size,
                 "Surfaces with fewer splats get id 0xFFFFFFFF (no surface); not merged")
      ->default_val(1)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
  app.add_option("--method", o.method,
                 "robust (grow from core splats) or components (connected components)")
      ->default_val("robust")
      ->check(CLI::IsMember({"robust", "components"}));
  splatkit::tools::add_robust_options(app, o.robust);
  app.add_option("--report", o.paths.report, "Write the surfaces and their sizes as JSON here");
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_segment_surfaces(o, progress);
  });
}
