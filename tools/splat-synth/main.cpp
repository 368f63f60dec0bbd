// splat-synth: synthetic ground-truth shapes (sphere, torus, CAD-like part, two interpenetrating
// spheres, cube) sampled with exact normals, radii and smooth-patch labels ("patch_id"), written
// in any output format. The work is splatkit::make_shape (lib/splatkit/synthetic_shapes.h).
#include <nlohmann/json.hpp>

#include "formats/write_cloud.h"
#include "splatkit/error.h"
#include "splatkit/progress.h"
#include "splatkit/synthetic_shapes.h"
#include "splatkit/tool.h"
#include "splatkit/version.h"

namespace {

nlohmann::json describe(const splatkit::ShapeOptions& o, const splatkit::SplatCloud& cloud,
                        bool colors) {
  const splatkit::Bounds b = compute_bounds(cloud);
  nlohmann::json m;
  m["tool"] = "splat-synth";
  m["version"] = splatkit::kVersion;
  m["options"] = {{"shape", splatkit::shape_kind_name(o.kind)},
                  {"points", o.points},
                  {"seed", o.seed},
                  {"noise", o.noise},
                  {"random", o.random},
                  {"keep_inside", o.keep_inside},
                  {"colors", colors}};
  m["counts"] = {{"points", cloud.size()}, {"faces", 0}};
  if (!b.empty())
    m["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
  m["patches"] = splatkit::shape_patch_names(o);
  m["history"] = nlohmann::json::array();
  return m;
}

}  // namespace

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
      "  $ splat-synth torus torus.xyz -n 2000 --random --seed 7  # i.i.d. uniform sample as text\n"
      "  $ splat-synth cube - | splat-info -            # .splk on stdout\n");
  std::string shape, output;
  splatkit::ShapeOptions options;
  splatkit::WriteOptions write;
  bool no_color = false;
  auto& app = tool.app();
  app.add_option("SHAPE", shape, "sphere, torus, cad, two-spheres or cube")
      ->required()
      ->check(CLI::IsMember({"sphere", "torus", "cad", "two-spheres", "cube"}));
  app.add_option("OUT", output, "Output file ('-' = .splk on stdout)")->required();
  app.add_option("-n,--points", options.points, "Number of points (stratified: approximately)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30))
      ->default_val(10000);
  app.add_option("--seed", options.seed, "Random seed (same seed, same bytes)")->default_val(1);
  app.add_option(
         "--noise", options.noise,
         "Gaussian noise along the true normal, std. dev. as a fraction of the bounding-box "
         "diagonal (normals stay exact)")
      ->check(CLI::Range(0.0, 1.0))
      ->default_val(0.0);
  app.add_flag("--random", options.random,
               "i.i.d. uniform sampling (exactly -n points) instead of stratified");
  app.add_flag("--keep-inside", options.keep_inside,
               "two-spheres: keep the part of each sphere inside the other (two whole spheres)");
  app.add_flag("--no-color", no_color, "Leave out the colours (smaller files)");
  auto* ascii = app.add_flag("--ascii", write.ascii, "PLY: write ASCII");
  app.add_flag("--big-endian", write.big_endian, "PLY: write binary big-endian")->excludes(ascii);
  return tool.run(argc, argv, [&] {
    options.kind = splatkit::parse_shape_kind(shape);
    if (options.keep_inside && options.kind != splatkit::ShapeKind::kTwoSpheres)
      splatkit::throw_usage("--keep-inside applies to two-spheres only");
    splatkit::Progress progress(tool.name(), tool.quiet() || output == "-");
    splatkit::LoadedCloud doc;
    doc.cloud = splatkit::make_shape(options);
    if (no_color) doc.cloud.colors.clear();
    doc.format = "synthetic";
    doc.metadata = describe(options, doc.cloud, !no_color);
    splatkit::write_cloud(doc, output, write);
    progress.finish(doc.cloud.size());
  });
}
