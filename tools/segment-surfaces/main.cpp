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
      "angle: half the sharp angle when the normals are noisy or the components run across "
      "creases) so blended creases do not merge faces; on other clean normals it gives the "
      "components. --method components: the connected "
      "components of the continuous edges. Then (either method) the borders are refined: each "
      "surface of at least --merge-below splats is fitted with a plane, sphere or cylinder, and "
      "for --refine-rounds rounds every splat on a border between surfaces, and every splat of "
      "a fragment (a surface under --merge-below splats, or one a larger neighbour's fit "
      "explains), joins the adjacent surface whose fit is nearest (across a convex crease the "
      "one it lies outside of, across a concave one the one it lies inside of) and whose "
      "normal is within 120 degrees of its own; a surface no primitive explains (free-form) "
      "keeps its border. Fragments left over join the neighbour they share the most graph "
      "edges with. Then planar surfaces are split off and joined, and their borders settled, "
      "by their fitted planes (--coplanar-scales). Ids are numbered in the order of each surface's "
      "lowest splat index and "
      "do "
      "not depend on the thread count. OUT .splk ('-' = stdout) adds the SURF chunk; OUT .ply "
      "writes a binary PLY with the extra vertex properties surface_id (uint32) and class "
      "(uint8: 0 smooth, 1 edge, 2 intersection). --min-size N, applied last: surfaces with "
      "fewer than N splats get no id (surface_id 4294967295 = 0xFFFFFFFF) and the remaining "
      "ones are numbered again 0.. in the same order.",
      "  $ segment-surfaces part-graph.splk part-surf.splk --report surfaces.json\n"
      "  $ segment-surfaces part-graph.splk part-surf.ply --min-size 50\n"
      "  $ segment-surfaces part-graph.splk part-surf.splk --refine-rounds 0 --merge-below 1  "
      "# segmentation only\n");
  splatkit::apps::SegmentSurfacesOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input .splk from build-splat-graph ('-' = stdin)",
                  "Output .splk or .ply ('-' = .splk on stdout)");
  app.add_option("--min-size", o.min_size,
                 "Surfaces with fewer splats (after merging) get id 0xFFFFFFFF (no surface)")
      ->default_val(1)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
  app.add_option("--method", o.method,
                 "robust (grow from core splats) or components (connected components)")
      ->default_val("robust")
      ->check(CLI::IsMember({"robust", "components"}));
  splatkit::tools::add_robust_options(app, o.robust);
  app.add_option("--refine-rounds", o.refine_rounds,
                 "Rounds of moving border and fragment splats to the best-fitting adjacent "
                 "surface (0: no refinement)")
      ->default_val(8)
      ->check(CLI::Range(uint32_t{0}, uint32_t{1000}));
  app.add_option("--merge-below", o.merge_below,
                 "Surfaces with fewer splats are fragments: their splats join the best-fitting "
                 "neighbour, the rest merge into the neighbour sharing the most edges, and a "
                 "fragment with no edge out joins the surface of a splat that nearly touches it "
                 "(centres within twice the radii: a stray lifted off by noise) (1: none)")
      ->default_val(50)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
  app.add_option("--coplanar-scales", o.coplanar_scales,
                 "Last, by fitted planes (robust; planar: the normals' median angle from the "
                 "plane within 25 degrees): a planar surface of at least --merge-below splats "
                 "gives up the connected pieces of it that are off its plane (beyond S robust "
                 "residual scales, normals over 30 degrees from its normal) and planar on a "
                 "plane of their own (a roof face joined over a blended valley), and so do "
                 "faces of 20 splats or more, flat within their noise and two splats wide (a "
                 "ledge); then two surfaces join when the larger is planar, their planes are "
                 "within 30 degrees and the smaller's splats lie on the larger's plane (median "
                 "distance within S scales, its noise and relief, or one splat diameter; within "
                 "4.685 scales of the plane fitted to both, the fit's own cut-off, when the "
                 "smaller is under half the larger's size: a bay of a facade) — and, with planes "
                 "within 10 degrees, also "
                 "when they share no edge (the wings of a facade); a group is judged by the "
                 "plane of all its splats. Last, a splat on the border of two planar surfaces "
                 "whose planes are over 30 degrees apart goes to the one whose plane it lies "
                 "nearer when that plane holds it (within S scales) and it is off its own plane "
                 "or on the other's side of the crease. Faces at a step or a crease stay apart "
                 "(0: none of this)")
      ->default_val(3.0)
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--report,--stats", o.paths.report,
                 "Write the surfaces and their sizes as JSON here");
  tool.add_threads_option();
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_segment_surfaces(o, progress);
  });
}
