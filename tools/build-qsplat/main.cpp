// build-qsplat: declares the options of apps::run_build_qsplat (lib/apps) and calls it.
#include <malloc.h>

#include <climits>

#include "apps/run_build_qsplat.h"
#include "apps/run_merge_qsplat.h"
#include "splatkit/error.h"
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
      "points. With --merge, IN... are the .qs files of tiles (each built from its tile's own "
      "points) and OUT one tree: new levels over the tiles' roots, the tiles' trees below them "
      "quantised again in their new parents' frames (docs/tools/build-qsplat.md).",
      "  $ build-qsplat bunny.ply bunny.qs\n"
      "  $ estimate-normals scan.las - | build-qsplat - scan.qs --no-color --report qs.json\n"
      "  $ build-qsplat --merge lod/tile_*.qs survey.qs  # tiles' trees, one tree\n");
  splatkit::apps::BuildQSplatOptions o;
  auto& app = tool.app();
  std::vector<std::string> files;  // IN... OUT
  app.add_option("IN... OUT", files,
                 "Input splats with normals and radii, or a mesh, any format ('-' = stdin; a "
                 "tile of splat-tile gives its own points only), then the output .qs ('-' = "
                 "stdout). Several inputs with --merge only: the tiles' .qs files")
      ->required()
      ->expected(2, -1);
  app.callback([&] {
    o.paths.input = files.front();
    o.paths.output = files.back();
  });
  bool merge = false;
  app.add_flag("--merge", merge,
               "IN... are .qs files of tiles of one survey (all with colours or none): write one "
               "tree with new levels over the tiles' roots");
  app.add_flag("--no-color", o.no_color, "Leave the colours out (4 instead of 6 bytes per node)");
  app.add_flag("--centroid-spheres", o.centroid_rule,
               "Node spheres by the original rule (centroid of the children + farthest) instead "
               "of the tighter sphere around the children");
  app.add_option("--report,--stats", o.paths.report,
                 "Write the counts (leaves, dropped points, nodes, levels, bytes per leaf, mean "
                 "node radius against the centroid rule) and timings as JSON");
  tool.add_columns_option(o.read.columns);
  tool.add_threads_option();
  // Each phase frees arrays of tens of MB (the mesh's faces, the leaves, the tree's work
  // arrays) and the next allocates others of like size: kept in the heap (no block mapped on its
  // own, the top never trimmed), they are reused instead of unmapped and faulted in afresh. A 4M-
  // vertex mesh: 175k -> 116k page faults, 0.38 -> 0.28 s of system time, peak RSS 388 -> 470 MB.
  tool.reuse_freed_blocks();
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    if (merge) {
      for (const char* option : {"--no-color", "--centroid-spheres", "--columns"})
        if (app.count(option) > 0)
          splatkit::throw_usage(std::string(option) +
                                " does not apply to --merge (the tiles' files were built with "
                                "theirs)");
      splatkit::apps::MergeQSplatOptions m;
      m.paths = o.paths;
      m.more_inputs.assign(files.begin() + 1, files.end() - 1);
      return splatkit::apps::run_merge_qsplat(m, progress);
    }
    if (files.size() > 2)
      splatkit::throw_usage("several inputs are for --merge (the .qs files of tiles)");
    return splatkit::apps::run_build_qsplat(o, progress);
  });
}
