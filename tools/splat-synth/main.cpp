// splat-synth: declares the options of apps::run_splat_synth (lib/apps) and calls it.
#include "apps/run_splat_synth.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-synth",
      "Make a synthetic ground-truth point cloud: SHAPE (sphere, torus, cad, two-spheres, cube) "
      "sampled area-uniformly with exact outward normals, splat radii that cover the surface, and "
      "the true smooth patch of every point as the uint32 attribute patch_id. The output format "
      "follows OUT's extension (.ply .xyz .off .splk; '-' writes .splk to stdout).",
      "  $ splat-synth sphere sphere.ply                 # 10000 points, stratified\n"
      "  $ splat-synth cad cad.ply -n 30000 --noise 0.001  # CAD-like part with noise along "
      "normals\n"
      "  $ splat-synth two-spheres spheres.ply --keep-inside  # both whole spheres, red and blue\n"
      "  $ splat-synth torus torus.xyz -n 2000 --random --seed=7  # i.i.d. uniform sample as text\n"
      "  $ splat-synth cad lines.ply -n 50000 --scan-lines 4  # scan lines, 4x denser along\n"
      "  $ splat-synth cube - | splat-info -            # .splk on stdout\n"
      "  $ splat-synth city city.splk -n 10000000 --walkthrough city.path.json\n");
  splatkit::apps::SplatSynthOptions o;
  auto& app = tool.app();
  app.add_option("SHAPE", o.shape,
                 "sphere, torus, cad, two-spheres, cube, or city (a grid of buildings with walls, "
                 "floor slabs and roofs on a ground plane, metres, sampled on a regular grid; "
                 "for occlusion culling; --blocks, --walkthrough)")
      ->required()
      ->check(CLI::IsMember({"sphere", "torus", "cad", "two-spheres", "cube", "city"}));
  app.add_option("OUT", o.output, "Output file ('-' = .splk on stdout)")->required();
  app.add_option("-n,--points", o.sample.points, "Number of points (stratified: approximately)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30))
      ->default_val(10000);
  app.add_option("--seed", o.sample.seed, "Random seed (same seed, same bytes)")->default_val(1);
  app.add_option("--noise", o.sample.noise,
                 "Gaussian noise along the true normal, std. dev. as a fraction of the "
                 "bounding-box diagonal (normals stay exact)")
      ->check(splatkit::finite_range(0.0, 1.0))
      ->default_val(0.0);
  app.add_flag("--random", o.sample.random,
               "i.i.d. uniform sampling (exactly -n points) instead of stratified");
  app.add_option("--scan-lines", o.sample.scan_lines,
                 "Sample along parallel scan lines, A times denser along a line than across "
                 "(i.i.d. along each line; implies --random; planes: rows, surfaces of "
                 "revolution: circles)")
      ->check(splatkit::finite_range(1.0, 1000.0));
  app.add_flag("--keep-inside", o.sample.keep_inside,
               "two-spheres: keep the part of each sphere inside the other (two whole spheres)");
  app.add_flag("--no-color", o.no_color, "Leave out the colours (smaller files)");
  app.add_flag("--texture", o.sample.texture,
               "Colours and an intensity attribute as a scanner records them: a smooth texture "
               "over the surface with sensor noise (default: one flat colour, no intensity; the "
               "points are the same)");
  app.add_option("--blocks", o.city_blocks, "city: buildings per side of the grid (2..64)")
      ->default_val(8);
  app.add_option("--walkthrough", o.walkthrough,
                 "city: also write a street-level walkthrough camera path (JSON for splat-view "
                 "--path)")
      ->type_name("PATH.json");
  app.add_option("--walk-frames", o.walk_frames, "city: cameras on the walkthrough (2..100000)")
      ->default_val(60);
  tool.add_ply_encoding_options(o.write.ascii, o.write.big_endian);
  tool.add_threads_option();  // the writers checksum and copy large outputs in parallel
  app.add_option("--report,--stats", o.report,
                 "Write the counts, timings and peak RSS as JSON here");
  return tool.run_stage(argc, argv, o.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_splat_synth(o, progress);
  });
}
