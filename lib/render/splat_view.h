// splat-view's work, callable without the command line: read a splat file, render one frame or a
// turntable, write the images and optionally a JSON report.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "render/frame_renderer.h"
#include "splatkit/progress.h"

namespace splatkit::render {

// Albedo per splat: the file's colours, or false colours from the splat graph (splat_palette.h),
// lit by the chosen shading.
enum class ColorBy {
  kFile,     // the file's colours (grey without)
  kSurface,  // a colour per surface id (needs SURF or a surface_id attribute: segment-surfaces)
  kSharp,    // splats with a sharp edge red, the rest green (needs CLAS or a class attribute)
  kClipped,  // splats with clip partners orange, the rest grey (needs CLIP: build-splat-graph)
};

struct SplatViewOptions {
  std::string input;   // any format read_cloud reads; "-" = stdin
  std::string output;  // image path (extension picks the format); with a turntable it holds one
                       // printf integer conversion such as %04d for the frame number
  // Camera: either eye (+ target, default the model's centre) or an orbit view (azimuth,
  // elevation in degrees, optional distance from the bounding sphere's centre in scene units);
  // neither gives the default three-quarter view.
  std::optional<Vec3f> eye, target;
  std::optional<std::array<float, 2>> view;
  std::optional<float> view_distance;
  Vec3f up{0, 0, 1};
  float fov_y_deg = 40;
  int width = 1280, height = 720;
  int turntable = 0;       // > 0: that many frames, one full turn about `up` around the target
  std::string stats_path;  // JSON report, or empty
  int threads = 0;         // recorded in the report (the caller sets the TBB limit)
  ColorBy color_by = ColorBy::kFile;
  RenderOptions render;  // render.clip, render.surface_ids: use the file's CLIP / surface ids
};

struct SplatViewSummary {
  std::size_t frames = 0;
  uint64_t splats = 0;       // per frame
  double frame_seconds = 0;  // sum over frames, rendering only
  double load_seconds = 0, write_seconds = 0;
};

// Throws Error(kUsage) for conflicting options (before reading the input), Error(kBadInput) for
// unreadable input, a cloud without normals/radii, a malformed graph chunk, or a colour mode whose
// data the file lacks (the message names the tool to run first), Error(kOutput) when writing
// fails.
SplatViewSummary run_splat_view(const SplatViewOptions& options,
                                const ProgressFn& progress = no_progress());

// The frame file name for frame `index` of a turntable pattern (validated by run_splat_view).
std::string frame_path(const std::string& pattern, int index);

}  // namespace splatkit::render
