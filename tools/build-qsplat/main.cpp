// build-qsplat: declares the options of apps::run_build_qsplat (lib/apps) and calls it.
#include "apps/run_build_qsplat.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "build-qsplat",
      "Build a QSplat bounding-sphere hierarchy [Rusinkiewicz00] and write it as a .qs file "
      "(version 11, big-endian, readable by the original QSplat viewer). IN is splats with "
      "normals and radii (run estimate-normals first otherwise) or a triangle mesh (PLY/OFF with "
      "faces: normals and radii come from the adjacent triangles; unused vertices are dropped). "
      "Every decoded sphere lies inside its decoded parent; an interior node's contains its "
      "splats, a leaf's is the cell nearest the splat's disc (formats/qsplat.md). At least 5 "
      "points.",
      "  $ build-qsplat bunny.ply bunny.qs\n"
      "  $ estimate-normals scan.las - | build-qsplat - scan.qs --no-color --report qs.json\n");
  splatkit::apps::BuildQSplatOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths,
                  "Input splats with normals and radii, or a mesh, any format ('-' = stdin)",
                  "Output .qs ('-' = stdout)");
  app.add_flag("--no-color", o.no_color, "Leave the colours out (4 instead of 6 bytes per node)");
  app.add_flag("--centroid-spheres", o.centroid_rule,
               "Node spheres by the original rule (centroid of the children + farthest) instead "
               "of the tighter sphere around the children");
  app.add_option("--report,--stats", o.paths.report,
                 "Write the counts (leaves, dropped points, nodes, levels, bytes per leaf, mean "
                 "node radius against the centroid rule) and timings as JSON");
  tool.add_columns_option(o.read.columns);
  tool.add_threads_option();
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_build_qsplat(o, progress);
  });
}
