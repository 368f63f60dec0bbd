// build-spt: declares the options of apps::run_build_spt (lib/apps) and calls it.
#include <CLI/CLI.hpp>

#include "apps/run_build_spt.h"
#include "apps/run_merge_spt.h"
#include "splatkit/error.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "build-spt",
      "Build a Sequential Point Tree [Dachsbacher03] and write it as an .spt file "
      "(formats/spt.md): "
      "an octree of discs fitted to their children, each with its geometric error (perpendicular, "
      "tangential and colour terms) turned into a distance interval [r_min, r_max), the list "
      "sorted by r_max descending so that a renderer draws a prefix. IN is splats with normals "
      "and radii (run estimate-normals first otherwise). Entries are 16 bytes (quantised) by "
      "default, 40 with --precision full. With --merge, IN... are the .spt files of tiles "
      "(each built from its tile's own points) and OUT one list over them all: new nodes above "
      "the tiles' roots, the tiles' entries re-quantised (docs/tools/build-spt.md).",
      "  $ build-spt scan.splk scan.spt  # splats: after estimate-normals\n"
      "  $ estimate-normals scan.las - | build-spt - scan.spt --report spt.json\n"
      "  $ splat-view scan.spt -o far.png --view 30,20,50 --spt-error 1\n"
      "  $ build-spt --merge lod/tile_*.spt survey.spt  # tiles' lists, one list\n");
  splatkit::apps::BuildSptOptions o;
  auto& app = tool.app();
  std::vector<std::string> files;  // IN... OUT
  app.add_option("IN... OUT", files,
                 "Input splats with normals and radii, any format ('-' = stdin; a tile of "
                 "splat-tile gives its own points only), then the output .spt ('-' = stdout). "
                 "Several inputs with --merge only: the tiles' .spt files")
      ->required()
      ->expected(2, -1);
  app.callback([&] {
    o.paths.input = files.front();
    o.paths.output = files.back();
  });
  bool merge = false;
  app.add_flag("--merge", merge,
               "IN... are .spt files of tiles of one survey (same --epsilon, --color-weight and "
               "--precision): write one list with new nodes above the tiles' roots");
  app.add_option("--epsilon", o.epsilon,
                 "Screen error in radians the stored distances are stated for (r_min = e_g / E); "
                 "viewers rescale to their own error, so it only sets the stored scale")
      ->capture_default_str();
  app.add_option("--color-weight", o.color_weight,
                 "L: weight of the colour deviation in a node's error (e_c = L * diameter * "
                 "deviation in [0, 1]); 0 ignores colour")
      ->capture_default_str();
  std::string precision = "compact";
  app.add_option("--precision", precision,
                 "compact: 16-byte quantised entries; full: 40-byte float entries")
      ->check(CLI::IsMember({"compact", "full"}))
      ->capture_default_str();
  app.add_option("--report,--stats", o.paths.report,
                 "Write the counts (entries, entries per point, depth, dropped empty intervals), "
                 "time per phase, points/s and peak RSS as JSON");
  tool.add_columns_option(o.read.columns);
  tool.add_threads_option();
  tool.add_memory_options(o.memory,
                          "The tree is built in passes that run through the splats in Morton "
                          "order, so a pass holds few of them at a time; the output is the same");
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    if (merge) {
      for (const char* option :
           {"--epsilon", "--color-weight", "--precision", "--columns", "--max-memory", "--tmp-dir"})
        if (app.count(option) > 0)
          splatkit::throw_usage(std::string(option) +
                                " does not apply to --merge (the tiles' files were built with "
                                "theirs)");
      splatkit::apps::MergeSptOptions m;
      m.paths = o.paths;
      m.more_inputs.assign(files.begin() + 1, files.end() - 1);
      return splatkit::apps::run_merge_spt(m, progress);
    }
    if (files.size() > 2)
      splatkit::throw_usage("several inputs are for --merge (the .spt files of tiles)");
    o.full = precision == "full";
    return splatkit::apps::run_build_spt(o, progress);
  });
}
