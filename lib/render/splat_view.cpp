#include "render/splat_view.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <regex>
#include <vector>

#include "formats/read_cloud.h"
#include "render/scene_from_document.h"
#include "render/splat_palette.h"
#include "render/write_image.h"
#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/seconds_since.h"

namespace splatkit::render {

namespace {

const std::regex& frame_pattern() {
  static const std::regex re("%0?[0-9]*d");
  return re;
}

void check_options(const SplatViewOptions& o) {
  if (o.eye && o.view) throw_usage("--eye and --view are alternatives; give one of them");
  if (o.target && !o.eye) throw_usage("--target needs --eye");
  if (o.view_distance && !o.view) throw_usage("a view distance needs --view");
  if (o.turntable < 0) throw_usage("--turntable must be positive");
  if (o.turntable > 0) {
    const auto begin = std::sregex_iterator(o.output.begin(), o.output.end(), frame_pattern());
    if (std::distance(begin, std::sregex_iterator()) != 1 ||
        std::count(o.output.begin(), o.output.end(), '%') != 1)
      throw_usage(
          "--turntable needs an output name with one frame number field such as %04d, got '" +
          o.output + "'");
  }
  check_output_format(o.turntable > 0 ? frame_path(o.output, 0) : o.output);
}

Camera base_camera(const SplatViewOptions& o, const BoundingSphere& bounds) {
  if (o.eye) {
    Camera c;
    c.eye = *o.eye;
    c.target = o.target ? *o.target : bounds.center;
    c.up = o.up;
    c.fov_y_deg = o.fov_y_deg;
    c.width = o.width;
    c.height = o.height;
    return c;
  }
  const float az = o.view ? (*o.view)[0] : kDefaultAzimuthDeg;
  const float el = o.view ? (*o.view)[1] : kDefaultElevationDeg;
  return orbit_camera(bounds, az, el, o.view_distance, o.up, o.fov_y_deg, o.width, o.height);
}

// Rotates the eye about the axis through the target along `up` (Rodrigues).
Camera turned(const Camera& c, float angle_rad) {
  const Vec3f k = normalized(c.up);
  const Vec3f v = c.eye - c.target;
  const float cs = std::cos(angle_rad), sn = std::sin(angle_rad);
  Camera out = c;
  out.eye = c.target + v * cs + cross(k, v) * sn + k * (dot(k, v) * (1 - cs));
  return out;
}

const char* blend_name(BlendMode m) { return m == BlendMode::kZRange ? "zrange" : "zthreshold"; }

// Replaces the scene's colours by the false colours of `by`, or says which tool makes the data.
void apply_colors(ColorBy by, DocumentScene& d, const std::string& name) {
  RenderScene& scene = d.scene;
  switch (by) {
    case ColorBy::kFile:
      return;
    case ColorBy::kSurface:
      if (scene.surface_ids.empty())
        throw_bad_input(name,
                        "--shade surface needs surface ids (a SURF chunk or a surface_id "
                        "attribute); run segment-surfaces first");
      scene.colors = surface_colors(scene.surface_ids);
      return;
    case ColorBy::kSharp:
      if (d.classes.empty())
        throw_bad_input(name,
                        "--shade sharp needs splat classes (a CLAS chunk or a class attribute); "
                        "run build-splat-graph first");
      scene.colors = sharp_colors(d.classes);
      return;
    case ColorBy::kClipped:
      if (scene.clip.num_splats() == 0)  // no CLIP chunk
        throw_bad_input(name,
                        "--shade clipped needs clip partners (a CLIP chunk, .splk only); run "
                        "build-splat-graph first");
      scene.colors = clipped_colors(scene.clip);
      return;
  }
}

nlohmann::json frame_json(const FrameStats& s, double write_s) {
  auto ms = [](double sec) { return std::round(sec * 1e6) / 1e3; };
  return {{"splats_in", s.splats_in},
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
}

// Distinct ids, not counting kNoSurfaceId.
uint64_t surface_count(const std::vector<uint32_t>& ids) {
  std::vector<uint32_t> sorted(ids);
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  return sorted.size() - (!sorted.empty() && sorted.back() == kNoSurfaceId);
}

void write_stats(const std::string& path, const nlohmann::json& j) {
  OutputFile file(path);
  file.write(j.dump(2) + "\n");
  file.commit();
}

}  // namespace

std::string frame_path(const std::string& pattern, int index) {
  std::smatch m;
  if (!std::regex_search(pattern, m, frame_pattern())) return pattern;
  char buf[64];
  std::snprintf(buf, sizeof buf, m.str().c_str(), index);
  return m.prefix().str() + buf + m.suffix().str();
}

SplatViewSummary run_splat_view(const SplatViewOptions& o, const ProgressFn& progress) {
  check_options(o);
  SplatViewSummary summary;
  const auto t0 = Clock::now();
  progress(0.0, "reading");
  const std::string name = display_name(o.input);
  DocumentScene document = scene_from_document(read_cloud(o.input), name);
  apply_colors(o.color_by, document, name);
  const RenderScene& scene = document.scene;
  summary.load_seconds = seconds_since(t0);
  const bool use_ids = o.render.surface_ids && !scene.surface_ids.empty();

  const Camera base = base_camera(o, scene.bounds);
  const int frames = o.turntable > 0 ? o.turntable : 1;
  RenderOptions render = o.render;
  render.planes = planes_for_output(o.output, use_ids);
  FrameRenderer renderer;
  Framebuffer frame;
  nlohmann::json per_frame = nlohmann::json::array();
  FrameStats last;
  for (int i = 0; i < frames; ++i) {
    progress(double(i) / frames, "rendering");
    const Camera camera =
        turned(base, 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / frames);
    last = renderer.render(scene, camera, render, frame);
    const auto w0 = Clock::now();
    write_image(frame, o.turntable > 0 ? frame_path(o.output, i) : o.output);
    const double write_s = seconds_since(w0);
    summary.frame_seconds += last.total_s;
    summary.write_seconds += write_s;
    per_frame.push_back(frame_json(last, write_s));
  }
  progress(1.0, "done");
  summary.frames = frames;
  summary.splats = scene.size();

  if (!o.stats_path.empty()) {
    nlohmann::json j = per_frame.back();
    j["input"] = name;
    j["width"] = o.width;
    j["height"] = o.height;
    j["threads"] = o.threads;
    j["blend"] = blend_name(o.render.blend);
    j["max_fragments"] = o.render.max_fragments;
    j["surface_ids"] = use_ids ? document.surface_source : "none";
    j["surfaces"] = use_ids ? surface_count(scene.surface_ids) : 0;
    j["clip"] = o.render.clip && scene.has_clip();
    j["clipped_splats"] = o.render.clip ? scene.clip.clipped_splats() : 0;
    j["clip_partners"] = o.render.clip ? scene.clip.partners.size() : 0;
    j["load_ms"] = std::round(summary.load_seconds * 1e6) / 1e3;
    if (frames > 1) {
      j["frames"] = per_frame;
      j["mean_frame_ms"] = std::round(summary.frame_seconds / frames * 1e6) / 1e3;
    }
    write_stats(o.stats_path, j);
  }
  return summary;
}

}  // namespace splatkit::render
