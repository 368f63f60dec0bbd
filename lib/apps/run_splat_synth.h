// splat-synth's work, callable without the command line: a synthetic ground-truth shape
// (splatkit/synthetic_shapes.h) with exact normals, radii and patch ids, written in any output
// format with a description of how it was made.
#pragma once

#include <string>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "splatkit/progress.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::apps {

struct SplatSynthOptions {
  std::string shape;      // sphere | torus | cad | two-spheres | cube | city
  std::string output;     // extension picks the format ("-": .splk on standard output)
  ShapeOptions sample;    // points, seed, noise, random, keep_inside; kind comes from `shape`
  bool no_color = false;  // leave out the colours
  WriteOptions write;     // ascii, big_endian (PLY)
  // city (splatkit/synthetic_city.h): buildings per side, and a JSON camera path of a street-level
  // walkthrough (splat-view --path) written beside the cloud when `walkthrough` is not empty.
  int city_blocks = 8;
  int walk_frames = 60;
  std::string walkthrough;
  std::string report;  // JSON report (counts, timings, peak RSS); empty = none; "-" = stdout
};

// Throws Error(kUsage) for bad options or an unusable OUT (before any work), Error(kOutput).
StageSummary run_splat_synth(const SplatSynthOptions& options,
                             const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
