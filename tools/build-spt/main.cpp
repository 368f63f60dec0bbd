// build-spt: declares the options of apps::run_build_spt (lib/apps) and calls it.
#include <CLI/CLI.hpp>

#include "apps/run_build_spt.h"
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
      "default, 40 with --precision full.",
      "  $ build-spt scan.splk scan.spt  # splats: after estimate-normals\n"
      "  $ estimate-normals scan.las - | build-spt - scan.spt --report spt.json\n"
      "  $ splat-view scan.spt -o far.png --view 30,20,50 --spt-error 1\n");
  splatkit::apps::BuildSptOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input splats with normals and radii, any format ('-' = stdin)",
                  "Output .spt ('-' = stdout)");
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
    o.full = precision == "full";
    return splatkit::apps::run_build_spt(o, progress);
  });
}
