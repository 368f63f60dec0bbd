// splat-view's work, callable without the command line: read a splat file, render one frame or a
// turntable (render/frame_renderer.h), write the images and optionally a JSON report.
#pragma once

#include <string>

#include "apps/stage_types.h"
#include "render/frame_renderer.h"
#include "render/occlusion_culler.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct SplatViewOptions {
  std::string input;       // any format read_cloud reads; "-" = stdin
  std::string output;      // image path (extension picks the format; "-" = PNG on stdout); with a
                           // turntable it holds one printf integer field such as %04d for the frame
  std::string stats_path;  // JSON report, or empty
  // Camera, as the command line gives it: either eye "x,y,z" (+ target "x,y,z", default the
  // model's centre) or an orbit view "AZ,EL[,DIST]" (degrees about `up` and above the horizon,
  // distance from the bounding sphere's centre in scene units); neither gives the default
  // three-quarter view. up "x,y,z" (default 0,0,1; turntables turn about it): when it is not
  // given, a top or bottom view takes render::automatic_up()'s axis (+y: a map); when it is given
  // with an eye and parallel to the viewing direction, Error(kUsage).
  std::string eye, target, view, up;
  float fov_y_deg = 40;  // in (0, 180)
  int width = 1280, height = 720;
  int turntable = 0;  // > 0: that many frames, one full turn about `up` around the target
                      // (render::turned_camera)
  std::string blend = "zthreshold";  // zthreshold[=EPS] (EPS > 0, scene units) | zrange
  // phong | normals | depth | flat, or false colours lit with phong: surface (per surface id),
  // sharp (splats with a sharp edge), clipped (splats with clip partners)
  std::string shade = "phong";
  std::string background;  // "r,g,b" sRGB in [0, 1], or empty for the default
  // A camera path (read_camera_path.h), or empty; one frame per camera, `output` then holds a
  // frame number field as for a turntable. Not with eye/view/turntable.
  std::string path;
  // Occlusion culling (render/occlusion_culler.h): none | frustum | hierarchical | chc | chc++.
  // Images are the same in every mode; plain scenes only (no QSplat, no clip partners unless
  // render.clip is off), not with --blend zbuffer.
  std::string occlusion = "none";
  std::string bvh_split = "median";  // median | sah (render/chunk_bvh.h)
  uint32_t bvh_leaf = 2048;          // splats per hierarchy leaf, at most
  // Diagnostic: count the splats each frame truly shows (render/count_visible_splats.h) into
  // the report as splats_visible, and render them alone (floor_ms: what any culling could at
  // best leave of a frame); costs a z-buffer pass and a render per frame, not counted in frame
  // times.
  bool count_visible = false;
  // render.max_fragments, cull_backfaces, clip (use the file's CLIP), surface_ids (use the file's
  // surface ids); blend, shade and background come from the texts above.
  render::RenderOptions render;
};

struct SplatViewSummary {
  std::size_t frames = 0;
  uint64_t splats = 0;       // in the scene (a .qs file's leaves, a .spt file's entries)
  uint64_t drawn = 0;        // summed over frames (a level of detail draws a few of them)
  double frame_seconds = 0;  // sum over frames, rendering only
  double load_seconds = 0, write_seconds = 0;
  double bvh_seconds = 0;            // building the chunk hierarchy (occlusion culling)
  render::OcclusionStats occlusion;  // summed over frames
  std::string hint;                  // for the summary line (e.g. a model that looks y-up)
  StageSummary line() const;         // for the command line's summary
};

// Throws Error(kUsage) for bad or conflicting options and unusable paths (before reading the
// input: --stats naming the input or the image, an image that cannot be created), Error(kBadInput)
// for unreadable input, splats that break check_splats.h, a malformed graph chunk, or a colour
// mode whose data the file lacks (the message names the tool to run first), Error(kOutput) when
// writing fails. The stats are written before the (last) image is committed: when they fail, the
// image is left as it was.
SplatViewSummary run_splat_view(const SplatViewOptions& options,
                                const ProgressFn& progress = no_progress());

// The frame file name for frame `index` of a turntable or path pattern (validated by
// run_splat_view): its one %d, %Nd or %0Nd field replaced by the number, each %% by a %.
std::string frame_path(const std::string& pattern, int index);

// Throws Error(kUsage) when `output`, the name of one image (no --turntable or --path), holds a
// frame number field (%d, %Nd, %0Nd): only those options fill it, so it is a forgotten option.
void check_single_image_name(const std::string& output);

}  // namespace splatkit::apps
