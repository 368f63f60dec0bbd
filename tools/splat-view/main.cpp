// splat-view: renders a splat file to an image on the CPU. Parses arguments only; the work is
// render::run_splat_view (lib/render).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/render_scene.h"
#include "render/splat_view.h"
#include "splatkit/error.h"
#include "splatkit/tool.h"

namespace {

using splatkit::Vec3f;
namespace render = splatkit::render;

Vec3f to_vec3(const std::vector<float>& v) { return {v[0], v[1], v[2]}; }

void parse_blend(const std::string& text, render::RenderOptions& r) {
  if (text == "zrange") {
    r.blend = render::BlendMode::kZRange;
    return;
  }
  const std::string prefix = "zthreshold";
  if (text.rfind(prefix, 0) != 0)
    splatkit::throw_usage("--blend must be zthreshold[=EPS] or zrange, got '" + text + "'");
  r.blend = render::BlendMode::kZThreshold;
  if (text.size() == prefix.size()) return;
  std::size_t used = 0;
  float eps = 0;
  try {
    if (text[prefix.size()] != '=') throw std::invalid_argument("");
    eps = std::stof(text.substr(prefix.size() + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() - prefix.size() - 1 || !(eps > 0))
    splatkit::throw_usage("--blend zthreshold=EPS needs a positive number, got '" + text + "'");
  r.epsilon = eps;
}

// --view AZ,EL[,DIST]: one text (CLI11 would print a fixed count for a 2-or-3 number list).
std::vector<float> parse_view(const std::string& text) {
  std::vector<float> out;
  std::size_t start = 0;
  bool ok = true;
  while (ok) {
    const std::size_t comma = text.find(',', start);
    const std::string part = text.substr(start, comma - start);
    std::size_t used = 0;
    try {
      out.push_back(std::stof(part, &used));
    } catch (const std::exception&) {
      used = 0;
    }
    ok = used != 0 && used == part.size() && std::isfinite(out.back());
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (!ok || out.size() < 2 || out.size() > 3)
    splatkit::throw_usage("--view needs AZ,EL or AZ,EL,DIST (numbers), got '" + text + "'");
  return out;
}

// --shade: a lighting mode, or a false-colour mode (lit with phong).
void parse_shade(const std::string& s, render::SplatViewOptions& o) {
  o.render.shade = render::ShadeMode::kPhong;
  o.color_by = render::ColorBy::kFile;
  if (s == "normals") o.render.shade = render::ShadeMode::kNormals;
  if (s == "depth") o.render.shade = render::ShadeMode::kDepth;
  if (s == "flat") o.render.shade = render::ShadeMode::kFlat;
  if (s == "surface") o.color_by = render::ColorBy::kSurface;
  if (s == "sharp") o.color_by = render::ColorBy::kSharp;
  if (s == "clipped") o.color_by = render::ColorBy::kClipped;
}

}  // namespace

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-view", "Render a splat file (positions, normals, radii, optional colours) to an image",
      "$ splat-view bunny.splk -o bunny.png                 # default three-quarter view\n"
      "$ splat-view scan.ply -o top.png --view 0,89 --width 1920 --height 1080\n"
      "$ splat-view part.splk -o part.exr --eye 3,2,1 --target 0,0,0  # float colour + Z, N AOVs\n"
      "$ splat-view part.splk -o 'turn_%04d.png' --turntable 36 --stats stats.json\n"
      "$ splat-view part-surf.splk -o surf.png --shade surface   # after segment-surfaces\n"
      "$ splat-view part-graph.splk -o soft.png --no-clip        # compare with clipping off\n");
  tool.add_threads_option();
  CLI::App& app = tool.app();
  render::SplatViewOptions o;
  std::vector<float> eye, target, up;
  std::string view_text;
  std::string blend = "zthreshold", shade = "phong";
  std::vector<float> background;
  bool no_clip = false, no_surface_ids = false;
  app.add_option("input", o.input, "Splat file (any format estimate-normals writes, .splk)")
      ->required();
  app.add_option("-o,--output", o.output,
                 "Image: .png (8-bit sRGB) or .exr (float RGBA + Z, N.X N.Y N.Z, and a uint "
                 "surface_id channel when the file has surface ids and --no-surface-ids is not "
                 "given); '-' = PNG to stdout")
      ->required();
  app.add_option("--eye", eye, "Camera position x,y,z")->delimiter(',')->expected(3);
  app.add_option("--target", target, "Point looked at x,y,z (default: model centre)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--up", up, "Up direction x,y,z (default 0,0,1)")->delimiter(',')->expected(3);
  app.add_option("--fov", o.fov_y_deg, "Vertical field of view, degrees")->default_val(40);
  app.add_option("--view", view_text,
                 "Orbit view AZ,EL[,DIST]: degrees around --up and above the horizon, distance "
                 "from the model centre (scene units; default frames the model)")
      ->type_name("AZ,EL[,DIST]");
  app.add_option("--width", o.width, "Image width, pixels")
      ->default_val(1280)
      ->check(CLI::Range(1, render::kMaxImageSide));
  app.add_option("--height", o.height, "Image height, pixels")
      ->default_val(720)
      ->check(CLI::Range(1, render::kMaxImageSide));
  app.add_option("--turntable", o.turntable,
                 "Render N frames in one turn around the model; OUT needs a %04d field")
      ->check(CLI::PositiveNumber);
  app.add_option("--blend", blend,
                 "Surface reconstruction: zthreshold[=EPS] (EPS in scene units, default twice "
                 "the mean splat radius) or zrange")
      ->default_val("zthreshold");
  app.add_option("--shade", shade,
                 "phong, normals, depth, flat (unlit albedo), or false colours lit with phong: "
                 "surface (a colour per surface id; needs segment-surfaces output), sharp "
                 "(splats with a sharp edge red, the rest green; needs build-splat-graph "
                 "output), clipped (splats with clip partners orange; needs a .splk from "
                 "build-splat-graph)")
      ->default_val("phong")
      ->check(CLI::IsMember({"phong", "normals", "depth", "flat", "surface", "sharp", "clipped"}));
  app.add_option("--max-fragments", o.render.max_fragments,
                 "A-buffer slots per pixel; on overflow the farthest fragment is dropped")
      ->default_val(8)
      ->check(CLI::Range(1, render::kMaxFragmentsPerPixel));
  app.add_flag("--cull-backfaces", o.render.cull_backfaces,
               "Skip splats facing away (closed, consistently oriented models only)");
  app.add_flag("--no-clip", no_clip,
               "Ignore the file's clip partners (CLIP chunk): edges as plain splats give them");
  app.add_flag("--no-surface-ids", no_surface_ids,
               "Ignore the file's surface ids (SURF chunk, else a surface_id attribute) in "
               "reconstruction: fragments of different surfaces blend");
  app.add_option("--background", background, "Background colour R,G,B (sRGB, 0..1)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--stats", o.stats_path, "Write a JSON report (counts, time per stage)");

  return tool.run(argc, argv, [&] {
    if (!eye.empty()) o.eye = to_vec3(eye);
    if (!target.empty()) o.target = to_vec3(target);
    if (!up.empty()) o.up = to_vec3(up);
    if (!view_text.empty()) {
      const std::vector<float> view = parse_view(view_text);
      o.view = std::array<float, 2>{view[0], view[1]};
      if (view.size() == 3) o.view_distance = view[2];
    }
    if (!background.empty())
      o.render.background = {render::srgb_to_linear(background[0]),
                             render::srgb_to_linear(background[1]),
                             render::srgb_to_linear(background[2])};
    parse_blend(blend, o.render);
    parse_shade(shade, o);
    o.render.clip = !no_clip;
    o.render.surface_ids = !no_surface_ids;
    o.threads = tool.threads();
    splatkit::Progress progress(tool.name(), tool.quiet() || o.output == "-");
    auto summary = render::run_splat_view(o, progress.callback());
    char extra[160];
    std::snprintf(extra, sizeof extra, "%zu frame(s), %.1f ms/frame (%.1f M splats/s)",
                  summary.frames, 1e3 * summary.frame_seconds / summary.frames,
                  summary.splats * summary.frames / summary.frame_seconds / 1e6);
    progress.finish(summary.splats, "splats", extra);
  });
}
