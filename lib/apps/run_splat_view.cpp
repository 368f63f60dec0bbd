#include "apps/run_splat_view.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <vector>

#include "apps/parse_triple.h"
#include "apps/read_camera_path.h"
#include "apps/stage.h"
#include "formats/read_cloud.h"
#include "formats/read_qsplat.h"
#include "formats/read_spt.h"
#include "render/background_image_writer.h"
#include "render/camera.h"
#include "render/chunk_bvh.h"
#include "render/count_visible_splats.h"
#include "render/occlusion_culler.h"
#include "render/qsplat_scene.h"
#include "render/reconstruct_pixel.h"
#include "render/render_scene.h"
#include "render/scene_from_document.h"
#include "render/setup_splats.h"
#include "render/splat_palette.h"
#include "render/spt_scene.h"
#include "render/subset_scene.h"
#include "render/write_image.h"
#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/same_file.h"
#include "splatkit/seconds_since.h"

namespace splatkit::apps {

using namespace render;

namespace {

// Albedo per splat: the file's colours, or false colours from the splat graph (splat_palette.h),
// lit by the chosen shading.
enum class ColorBy {
  kFile,     // the file's colours (grey without)
  kSurface,  // a colour per surface id (needs SURF or a surface_id attribute: segment-surfaces)
  kSharp,    // splats with a sharp edge red, the rest green (needs CLAS or a class attribute)
  kClipped,  // splats with clip partners orange, the rest grey (needs CLIP: build-splat-graph)
};

// A frame name pattern as printf reads it: text, one field "%d" (or "%Nd", "%0Nd", N < 10) for
// the frame number, and "%%" for a literal '%'.
struct FramePattern {
  std::string prefix, field, suffix;  // prefix and suffix with "%%" already made '%'
  int fields = 0;                     // the number fields found
  bool other = false;                 // a '%' that is neither "%%" nor a number field
};

FramePattern parse_frame_pattern(const std::string& pattern) {
  FramePattern f;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    std::string& text = f.fields == 0 ? f.prefix : f.suffix;
    if (pattern[i] != '%') {
      text += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      text += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    if (j < pattern.size() && pattern[j] == '0') ++j;
    const std::size_t digits = j;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j]))) ++j;
    if (j < pattern.size() && pattern[j] == 'd' && j - digits <= 1) {
      if (++f.fields == 1) f.field = pattern.substr(i, j + 1 - i);
      i = j;
    } else {
      f.other = true;
      text += '%';
    }
  }
  return f;
}

constexpr float kMaxSceneRadius = 1e18f;

// The options with their texts parsed and every number checked (NaN, infinity, range).
struct Resolved {
  std::optional<std::array<double, 3>> eye, target;  // the file's coordinates
  std::optional<std::array<float, 2>> view;
  std::optional<float> view_distance;
  Vec3f up{0, 0, 1};
  ColorBy color_by = ColorBy::kFile;
  RenderOptions render;
  OcclusionMode occlusion = OcclusionMode::kNone;
  BvhSplit split = BvhSplit::kMedian;
};

Vec3f to_vec3(const std::array<double, 3>& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// --view AZ,EL[,DIST]: two or three finite numbers, DIST positive.
void parse_view(const std::string& text, Resolved& r) {
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
    throw_usage("--view needs AZ,EL or AZ,EL,DIST (numbers), got '" + text + "'");
  r.view = std::array<float, 2>{out[0], out[1]};
  if (out.size() == 3) {
    if (!(out[2] > 0)) throw_usage("--view distance must be positive, got '" + text + "'");
    r.view_distance = out[2];
  }
}

void parse_blend(const std::string& text, RenderOptions& r) {
  if (text == "zrange" || text == "zbuffer") {
    r.blend = text == "zrange" ? BlendMode::kZRange : BlendMode::kZBuffer;
    return;
  }
  const std::string prefix = "zthreshold";
  if (text.rfind(prefix, 0) != 0)
    throw_usage("--blend must be zthreshold[=EPS], zrange or zbuffer, got '" + text + "'");
  r.blend = BlendMode::kZThreshold;
  if (text.size() == prefix.size()) return;
  std::size_t used = 0;
  float eps = 0;
  try {
    if (text[prefix.size()] != '=') throw std::invalid_argument("");
    eps = std::stof(text.substr(prefix.size() + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() - prefix.size() - 1 || !(eps > 0) || !std::isfinite(eps))
    throw_usage("--blend zthreshold=EPS needs a positive finite number, got '" + text + "'");
  r.epsilon = eps;
}

// --shade: a lighting mode, or a false-colour mode (lit with phong).
void parse_shade(const std::string& s, Resolved& r) {
  static const char* const kModes[] = {"phong",   "normals", "depth",  "flat",
                                       "surface", "sharp",   "clipped"};
  if (std::find(std::begin(kModes), std::end(kModes), s) == std::end(kModes))
    throw_usage("--shade must be phong, normals, depth, flat, surface, sharp or clipped, got '" +
                s + "'");
  r.render.shade = s == "normals" ? ShadeMode::kNormals
                   : s == "depth" ? ShadeMode::kDepth
                   : s == "flat"  ? ShadeMode::kFlat
                                  : ShadeMode::kPhong;
  r.color_by = s == "surface"   ? ColorBy::kSurface
               : s == "sharp"   ? ColorBy::kSharp
               : s == "clipped" ? ColorBy::kClipped
                                : ColorBy::kFile;
}

Vec3f parse_background(const std::string& text) {
  const std::array<double, 3> c = parse_triple(text, "--background", "r,g,b");
  for (double v : c)
    if (!(v >= 0 && v <= 1))
      throw_usage("--background must be three numbers in [0, 1] (sRGB), got '" + text + "'");
  return {srgb_to_linear(static_cast<float>(c[0])), srgb_to_linear(static_cast<float>(c[1])),
          srgb_to_linear(static_cast<float>(c[2]))};
}

// An --up the user gave must orient the image: refused when parallel to the viewing direction
// (without --up, automatic_up() picks another axis instead). eye == target is make_projection's
// error.
void check_explicit_up(const SplatViewOptions& o, const Vec3f& eye, const Vec3f& target,
                       const Vec3f& up) {
  if (eye != target && !up_orients_view(target - eye, up))
    throw_usage("--up " + o.up + " is parallel to the viewing direction from --eye to " +
                (o.target.empty() ? "the model centre" : "--target") +
                "; give another --up, or none for an automatic one");
}

Resolved resolve(const SplatViewOptions& o) {
  Resolved r;
  r.render = o.render;
  if (!o.eye.empty()) r.eye = parse_triple(o.eye, "--eye");
  if (!o.target.empty()) r.target = parse_triple(o.target, "--target");
  if (!o.up.empty()) r.up = to_vec3(parse_triple(o.up, "--up"));
  if (!o.view.empty()) parse_view(o.view, r);
  if (!o.background.empty()) r.render.background = parse_background(o.background);
  parse_blend(o.blend, r.render);
  parse_shade(o.shade, r);
  if (r.eye && r.view) throw_usage("--eye and --view are alternatives; give one of them");
  if (r.target && !r.eye) throw_usage("--target needs --eye");
  if (!(norm(r.up) > 0)) throw_usage("--up must not be zero");
  if (r.eye && r.target && !o.up.empty())
    check_explicit_up(o, to_vec3(*r.eye), to_vec3(*r.target), r.up);
  if (!(o.fov_y_deg > 0 && o.fov_y_deg < 180)) throw_usage("--fov must be in (0, 180) degrees");
  if (o.width < 1 || o.width > kMaxImageSide || o.height < 1 || o.height > kMaxImageSide)
    throw_usage("--width and --height must be in [1, " + std::to_string(kMaxImageSide) + "]");
  if (o.render.max_fragments < 1 || o.render.max_fragments > kMaxFragmentsPerPixel)
    throw_usage("--max-fragments must be in [1, " + std::to_string(kMaxFragmentsPerPixel) + "]");
  if (o.turntable < 0) throw_usage("--turntable must be positive");
  r.occlusion = parse_occlusion_mode(o.occlusion);
  if (o.bvh_split != "median" && o.bvh_split != "sah")
    throw_usage("--bvh-split must be median or sah, got '" + o.bvh_split + "'");
  r.split = o.bvh_split == "sah" ? BvhSplit::kSah : BvhSplit::kMedian;
  if (o.bvh_leaf < 1) throw_usage("--bvh-leaf must be at least 1");
  if (r.occlusion != OcclusionMode::kNone && r.render.blend == BlendMode::kZBuffer)
    throw_usage("--occlusion works with the A-buffer blends (zthreshold, zrange), not zbuffer");
  if (o.path == "-" && o.input == "-")
    throw_usage("--path - and IN - would both read standard input");
  if (!o.path.empty() && (r.eye || r.view || o.turntable > 0))
    throw_usage("--path gives the cameras; it does not go with --eye, --view or --turntable");
  if (o.turntable > 0 || !o.path.empty()) {
    const FramePattern f = parse_frame_pattern(o.output);
    if (f.fields != 1 || f.other)
      throw_usage(std::string(o.turntable > 0 ? "--turntable" : "--path") +
                  " needs an output name with one frame number field such as %04d (and %% for "
                  "a '%'), got '" +
                  o.output + "'");
  } else {
    check_single_image_name(o.output);
  }
  check_output_format(o.turntable > 0 || !o.path.empty() ? frame_path(o.output, 0) : o.output);
  return r;
}

// `p` (the file's coordinates) in the scene's local frame.
Vec3f local_point(const std::array<double, 3>& p, const RenderScene& scene) {
  return to_vec3({p[0] - scene.origin[0], p[1] - scene.origin[1], p[2] - scene.origin[2]});
}

Camera base_camera(const SplatViewOptions& o, const Resolved& r, const RenderScene& scene) {
  const BoundingSphere& bounds = scene.bounds;
  if (r.eye) {
    Camera c;
    c.eye = local_point(*r.eye, scene);
    c.target = r.target ? local_point(*r.target, scene) : bounds.center;
    if (o.up.empty()) {
      c.up = automatic_up(c.target - c.eye, r.up);
    } else {
      check_explicit_up(o, c.eye, c.target, r.up);
      c.up = r.up;
    }
    c.fov_y_deg = o.fov_y_deg;
    c.width = o.width;
    c.height = o.height;
    return c;
  }
  const float az = r.view ? (*r.view)[0] : kDefaultAzimuthDeg;
  const float el = r.view ? (*r.view)[1] : kDefaultElevationDeg;
  std::optional<float> distance = r.view_distance;
  if (o.turntable > 0 && !distance) {
    // The box fills the frame at one azimuth and may leave it at another: a turntable stays at
    // the farthest of its azimuths' framing distances (every 5°), so nothing leaves the frame.
    float d = 0;
    for (int k = 0; k < 72; ++k) {
      const Camera c = orbit_camera(bounds, az + 5.0f * static_cast<float>(k), el, std::nullopt,
                                    r.up, o.fov_y_deg, o.width, o.height);
      d = std::max(d, norm(c.eye - c.target));
    }
    distance = d;
  }
  return orbit_camera(bounds, az, el, distance, r.up, o.fov_y_deg, o.width, o.height);
}

const char* blend_name(BlendMode m) {
  return m == BlendMode::kZRange ? "zrange" : m == BlendMode::kZBuffer ? "zbuffer" : "zthreshold";
}

// Replaces the scene's colours by the false colours of `by`, or says which tool makes the data.
void apply_colors(ColorBy by, DocumentScene& d, const std::string& name) {
  RenderScene& scene = d.scene;
  auto need = [&](bool present, const char* what) {
    if (!present) throw_bad_input(name, what);
  };
  switch (by) {
    case ColorBy::kFile:
      return;
    case ColorBy::kSurface:
      need(!scene.surface_ids.empty(),
           "--shade surface needs surface ids (a SURF chunk or a surface_id attribute); run "
           "segment-surfaces first");
      scene.colors = surface_colors(scene.surface_ids);
      return;
    case ColorBy::kSharp:
      need(!d.classes.empty(),
           "--shade sharp needs splat classes (a CLAS chunk or a class attribute); run "
           "build-splat-graph first");
      scene.colors = sharp_colors(d.classes);
      return;
    case ColorBy::kClipped:
      need(scene.clip.num_splats() != 0,  // no CLIP chunk
           "--shade clipped needs clip partners (a CLIP chunk, .splk only); run "
           "build-splat-graph first");
      scene.colors = clipped_colors(scene.clip);
      return;
  }
}

nlohmann::json frame_json(const FrameStats& s, double write_s) {
  auto ms = [](double sec) { return std::round(sec * 1e6) / 1e3; };
  nlohmann::json j = {{"splats_in", s.splats_in},
                      {"splats_drawn", s.splats_drawn},
                      {"fragments", s.fragments},
                      {"pixels_covered", s.pixels_covered},
                      {"pixels_overflowed", s.pixels_overflowed},
                      {"splat_tiles_hidden", s.splats_hidden},
                      {"fragments_clipped", s.fragments_clipped},
                      {"time_ms",
                       {{"select", ms(s.select_s)},
                        {"setup", ms(s.setup_s)},
                        {"binning", ms(s.binning_s)},
                        {"rasterize", ms(s.raster_s)},
                        {"reconstruct", ms(s.reconstruct_s)},
                        {"shade", ms(s.shade_s)},
                        {"frame", ms(s.total_s)},
                        {"write", ms(write_s)}}},
                      {"splats_per_second", std::round(s.splats_per_second())}};
  if (s.lod.visited > 0)
    j["qsplat"] = {{"nodes_visited", s.lod.visited},
                   {"culled_frustum", s.lod.culled_frustum},
                   {"culled_cone", s.lod.culled_cone},
                   {"splats_selected", s.splats_in},
                   {"splats_drawn", s.splats_drawn}};
  if (s.lod.spt_prefix > 0) {
    const double prefix = static_cast<double>(s.lod.spt_prefix);
    j["spt"] = {
        {"prefix", s.lod.spt_prefix},
        {"culled_in_prefix", s.lod.spt_culled},
        {"culled_fraction", static_cast<double>(s.lod.spt_culled) / prefix},
        {"splats_selected", s.splats_in},
        {"splats_drawn", s.splats_drawn},
        {"select_ms", std::round(s.select_s * 1e6) / 1e3},

        {"selected_per_second", s.select_s > 0 ? std::round(s.splats_in / s.select_s) : 0.0}};
    if (s.lod.spt_cpu_s > 0) {  // --blend zbuffer: selection and drawing in one pass
      j["spt"]["drawn_as_points"] = s.lod.spt_points;
      j["spt"]["mean_diameter_px"] =
          s.splats_drawn > 0 ? s.lod.spt_diameter_px_sum / static_cast<double>(s.splats_drawn)
                             : 0.0;
      j["spt"]["select_cpu_ms"] = std::round(s.lod.spt_cpu_s * 1e6) / 1e3;
    }
  }
  return j;
}

nlohmann::json occlusion_json(const OcclusionStats& s) {
  auto ms = [](double sec) { return std::round(sec * 1e6) / 1e3; };
  return {{"nodes_traversed", s.nodes_traversed},
          {"queries", s.queries},
          {"multiqueries", s.multiqueries},
          {"queries_per_multiquery",
           s.multiqueries ? std::round(100.0 * s.multiquery_nodes / s.multiqueries) / 100 : 0.0},
          {"nodes_culled_frustum", s.culled_frustum},
          {"nodes_culled_occlusion", s.culled_occlusion},
          {"leaves_drawn", s.leaves_drawn},
          {"splats_drawn", s.splats_drawn},
          {"splats_culled", s.splats_culled},
          {"time_ms",
           {{"traversal", ms(s.traversal_s)},
            {"queries", ms(s.query_s)},
            {"depth", ms(s.depth_s)},
            {"splat_test", ms(s.splat_test_s)}}}};
}

std::string read_text_file(const std::string& path) {
  std::ostringstream text;
  if (path == "-") {  // standard input (IN is not: checked with the options)
    text << std::cin.rdbuf();
    if (std::cin.bad()) throw_bad_input(path, "cannot read the camera path");
    return text.str();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw_bad_input(path, std::string("cannot open the camera path: ") + std::strerror(errno));
  text << in.rdbuf();
  if (in.bad()) throw_bad_input(path, "cannot read the camera path");
  return text.str();
}

// Distinct ids, not counting kNoSurfaceId.
uint64_t surface_count(const std::vector<uint32_t>& ids) {
  std::vector<uint32_t> sorted(ids);
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  return sorted.size() - (!sorted.empty() && sorted.back() == kNoSurfaceId);
}

// A model drawn with the default +z up that looks as if +y were its up: longest along y, by a
// fifth over x, and deep along z (at least 0.45 of y). Many PLY models are y-up (the kitten:
// 0.65 x 1.0 x 0.59; the Nefertiti bust: 3.9 x 4.9 x 2.4), drawn z-up they lie on their side;
// surveys and terrain are flat along z (a city 80 x 52 x 9, CGAL's building scan 16 x 55 x 18).
// A hint only: a z-up car parked along y passes it too.
bool looks_y_up(std::span<const Vec3f> positions) {
  if (positions.empty()) return false;
  Vec3f lo = positions[0], hi = positions[0];
  for (const Vec3f& p : positions)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  const Vec3f e = hi - lo;
  return e.y > 1.2f * e.x && e.y >= e.z && e.z >= 0.45f * e.y;
}

}  // namespace

void check_single_image_name(const std::string& output) {
  if (parse_frame_pattern(output).fields > 0)
    throw_usage("'" + output +
                "' has a frame number field, which only --turntable or --path fill; name the "
                "one image without it");
}

std::string frame_path(const std::string& pattern, int index) {
  const FramePattern f = parse_frame_pattern(pattern);
  if (f.fields == 0) return pattern;
  char buf[32];  // a width below 10: at most 11 characters
  std::snprintf(buf, sizeof buf, f.field.c_str(), index);
  return f.prefix + buf + f.suffix;
}

StageSummary SplatViewSummary::line() const {
  // The count and the rates are of the splats drawn, not of those in the file: a .qs or .spt
  // frame draws a level of detail, a culled walkthrough what may show.
  char extra[200];
  std::snprintf(extra, sizeof extra, "%zu frame(s) of %llu splats, %.1f ms/frame (%.1f M drawn/s)",
                frames, static_cast<unsigned long long>(splats),
                1e3 * frame_seconds / static_cast<double>(frames),
                static_cast<double>(drawn) / frame_seconds / 1e6);
  return {drawn, "splats drawn", hint.empty() ? std::string(extra) : extra + ("; " + hint)};
}

SplatViewSummary run_splat_view(const SplatViewOptions& o, const ProgressFn& progress) {
  const Resolved r = resolve(o);
  // The path is checked before the scene loads, and read again in the scene's local frame once
  // its origin is known.
  const std::string path_text = o.path.empty() ? "" : read_text_file(o.path);
  std::vector<Camera> path;
  if (!o.path.empty())
    path = read_camera_path(path_text, o.path, r.up, o.fov_y_deg, o.width, o.height);
  const bool numbered = o.turntable > 0 || !o.path.empty();
  const int frames = !path.empty() ? int(path.size()) : o.turntable > 0 ? o.turntable : 1;
  auto image_path = [&](int i) { return numbered ? frame_path(o.output, i) : o.output; };
  Stage stage("splat-view", {o.input, image_path(0), o.stats_path}, "--stats");
  for (int i = 0; i < frames; ++i) {  // the other frames of a turntable or a path; the path file
    if ((i > 0 &&
         (same_file(o.input, image_path(i)) || same_file(o.stats_path, image_path(i), 1, 1))) ||
        (!o.path.empty() && same_file(o.path, image_path(i))))
      throw_usage("frame " + image_path(i) + " would overwrite an input or the stats");
    // Before any frame is written: a frame that could not be would stop the run midway.
    if (i > 0) check_can_create(image_path(i));
  }

  SplatViewSummary summary;
  const auto t0 = Clock::now();
  progress(0.0, "reading");
  const std::string& name = stage.input_name();
  DocumentScene document = stage.phase(nullptr, "reading " + name, [&] {
    if (looks_like_qsplat(stage.input().peek(6)))  // a .qs hierarchy: QSplat traversal
      return DocumentScene{make_qsplat_scene(read_qsplat(stage.input()), name), {}, "", ""};
    if (spt::looks_like_spt(stage.input().peek(8)))  // an .spt list: a prefix at the screen error
      return DocumentScene{make_spt_scene(read_spt(stage.input()), name), {}, "", ""};
    return scene_from_document(stage.read({}, progress), name);
  });
  apply_colors(r.color_by, document, name);
  const RenderScene& scene = document.scene;
  summary.load_seconds = seconds_since(t0);
  const bool use_ids = r.render.surface_ids && !scene.surface_ids.empty();

  // The default camera frames the whole scene, in float32 arithmetic that squares distances: a
  // scene wider than this (a splat 1e20 away from the rest, or a radius of 1e30) cannot be
  // framed. (With --eye or --path the outlier just stays out of view.)
  if (!r.eye && o.path.empty() && !(scene.bounds.radius <= kMaxSceneRadius)) {
    char what[256];
    std::snprintf(what, sizeof what,
                  "the splats span a bounding sphere of radius %.3g, beyond the %.0e the default "
                  "camera can frame in float32 (a far outlier or a huge radius? estimate-normals "
                  "--outliers removes outliers; --eye and --target place the camera)",
                  double(scene.bounds.radius), double(kMaxSceneRadius));
    throw_bad_input(name, what);
  }
  if (o.up.empty() && !r.eye && o.path.empty() && looks_y_up(scene.positions))
    summary.hint =
        "longest along y and not flat: if +y is up (as in many PLY models), give "
        "--up 0,1,0";
  const Camera base = base_camera(o, r, scene);
  if (!o.path.empty() && scene.origin != std::array<double, 3>{0, 0, 0})  // now in the local frame
    path = read_camera_path(path_text, o.path, r.up, o.fov_y_deg, o.width, o.height, scene.origin);
  RenderOptions render = r.render;
  render.planes = planes_for_output(o.output, use_ids);
  // Occlusion culling: the chunk hierarchy once, then per frame the splats to draw as a scene of
  // their own (subset_scene.h) rendered like the whole one.
  const bool culling = r.occlusion != OcclusionMode::kNone;
  if (culling && (scene.qsplat || scene.spt))
    throw_usage("--occlusion needs a plain splat file; " + name +
                (scene.qsplat ? " is a QSplat hierarchy" : " is a Sequential Point Tree"));
  if (culling && render.clip && scene.has_clip())
    throw_usage("--occlusion does not cull scenes with clip partners (" + name +
                "); give --no-clip or --occlusion none");
  ChunkBvh bvh;
  if (culling) {
    bvh = stage.phase(nullptr, "building the chunk hierarchy",
                      [&] { return build_chunk_bvh(scene, o.bvh_leaf, r.split); });
    summary.bvh_seconds = bvh.build_seconds;
  }
  std::unique_ptr<OcclusionCuller> culler;
  if (culling) culler = std::make_unique<OcclusionCuller>(scene, bvh);
  float margin = 0;
  if (culling) {
    const float eps = render.epsilon > 0 ? render.epsilon : 2.0f * scene.mean_radius;
    margin = depth_window(render.blend, eps, scene.max_radius, render.max_fragments);
  }
  RenderScene subset;
  nlohmann::json per_frame_occlusion = nlohmann::json::array();
  FrameRenderer renderer;
  Framebuffer frame;
  // Frame i is encoded and written on the writer's thread while frame i + 1 renders; the two
  // framebuffers take turns.
  BackgroundImageWriter writer;
  nlohmann::json per_frame = nlohmann::json::array();
  std::vector<double> frame_cpu;  // seconds, per frame
  FrameStats last;                // of the frame in flight
  auto finish_write = [&] {
    BackgroundImageWriter::Written done = writer.wait();
    summary.write_seconds += done.seconds;
    per_frame.push_back(frame_json(last, done.seconds));
    frame = std::move(done.frame);
    return std::move(done.file);
  };
  for (int i = 0; i < frames; ++i) {
    progress(double(i) / frames, "rendering");
    const Camera camera =
        !path.empty()
            ? path[i]
            : turned_camera(base, r.up,
                            2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / frames);
    Framebuffer target = std::move(frame);
    FrameStats stats;
    OcclusionStats occlusion;
    // Process CPU time of the frame (every thread; the writer's encoding of the previous frame
    // overlaps it): beside the wall time, a measure that a busy machine does not inflate.
    const std::clock_t cpu0 = std::clock();
    try {
      stats = stage.phase(nullptr, "rendering", [&] {
        if (!culling) return renderer.render(scene, camera, render, target);
        const auto c0 = Clock::now();
        const std::vector<uint32_t>& draw = culler->cull(make_projection(camera), r.occlusion,
                                                         margin, render.cull_backfaces, occlusion);
        subset_scene(scene, draw, subset);
        const double cull_s = seconds_since(c0);
        FrameStats f = renderer.render(subset, camera, render, target);
        f.select_s += cull_s;  // culling is the selection of what to draw
        f.total_s += cull_s;
        return f;
      });
    } catch (...) {
      if (writer.busy()) finish_write();  // an error writing the previous frame came first
      throw;
    }
    frame_cpu.push_back(double(std::clock() - cpu0) / CLOCKS_PER_SEC);
    if (writer.busy()) finish_write();
    writer.start(std::move(target), image_path(i), i + 1 < frames);
    summary.frame_seconds += stats.total_s;
    summary.drawn += stats.splats_drawn;
    summary.occlusion.add(occlusion);
    nlohmann::json oj = culling ? occlusion_json(occlusion) : nlohmann::json::object();
    if (o.count_visible && !scene.qsplat && !scene.spt) {
      // The floor of any culler with this renderer: the frame drawn from the shown splats alone
      // (not the same image: the splats that only blend are missing).
      const std::vector<uint32_t> shown =
          visible_splats(scene, make_projection(camera), render.cull_backfaces);
      oj["splats_visible"] = shown.size();
      RenderScene visible;
      subset_scene(scene, shown, visible);
      Framebuffer floor_image;
      const FrameStats f = renderer.render(visible, camera, render, floor_image);
      oj["floor_ms"] = std::round(f.total_s * 1e6) / 1e3;
    }
    per_frame_occlusion.push_back(oj);
    last = stats;
  }
  std::unique_ptr<OutputFile> last_image = finish_write();  // committed after the stats
  progress(1.0, "done");
  summary.frames = frames;
  summary.splats = scene.size();

  nlohmann::json j;
  if (!o.stats_path.empty()) {
    j = per_frame.back();
    j["width"] = o.width;
    j["height"] = o.height;
    j["blend"] = blend_name(r.render.blend);
    j["max_fragments"] = r.render.max_fragments;
    j["surface_ids"] = use_ids ? document.surface_source : "none";
    j["surfaces"] = use_ids ? surface_count(scene.surface_ids) : 0;
    j["clip"] = r.render.clip && scene.has_clip();
    j["clipped_splats"] = r.render.clip ? scene.clip.clipped_splats() : 0;
    j["clip_partners"] = r.render.clip ? scene.clip.partners.size() : 0;
    j["load_ms"] = std::round(summary.load_seconds * 1e6) / 1e3;
    j["occlusion"] = occlusion_mode_name(r.occlusion);
    if (o.count_visible)
      for (std::size_t f = 0; f < per_frame.size(); ++f)
        per_frame[f]["occlusion"] = per_frame_occlusion[f];
    if (culling) {
      j["bvh"] = {{"split", o.bvh_split},
                  {"leaf_size", o.bvh_leaf},
                  {"nodes", bvh.nodes.size()},
                  {"leaves", bvh.leaf_count},
                  {"sah_cost", std::round(bvh.sah_cost() * 1e3) / 1e3},
                  {"build_ms", std::round(bvh.build_seconds * 1e6) / 1e3}};
      j["occlusion_total"] = occlusion_json(summary.occlusion);
      for (std::size_t f = 0; f < per_frame.size(); ++f)
        per_frame[f]["occlusion"] = per_frame_occlusion[f];
      j["occlusion_stats"] = per_frame_occlusion.back();
    }
    if (frames > 1) {
      for (std::size_t f = 0; f < per_frame.size(); ++f)
        per_frame[f]["time_ms"]["frame_cpu"] = std::round(frame_cpu[f] * 1e6) / 1e3;
      j["frames"] = per_frame;
      j["mean_frame_ms"] = std::round(summary.frame_seconds / frames * 1e6) / 1e3;
    }
  }
  OutputFile* outputs[] = {last_image.get()};
  stage.commit(outputs, std::move(j));
  return summary;
}

}  // namespace splatkit::apps
