// splat-convert's work, callable without the command line: read a point cloud (PLY, XYZ/CSV,
// OFF, LAS, PCD, .splk) and write it as PLY, XYZ, OFF or .splk, keeping every attribute and the
// chunks; .splk gets the provenance. With more inputs, their points are concatenated (points
// only: faces and chunks are dropped; every input must hold the same fields), and inputs that
// carry splat-tile's `halo` attribute give their own points only, without the attribute: the
// tiles of a survey become one cloud again.
#pragma once

#include <string>
#include <vector>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct SplatConvertOptions {
  StagePaths paths;    // OUT's extension picks the format ("-": .splk) unless `format` says
  std::vector<std::string> more_inputs;  // read after paths.input, in order
  ReadOptions read;    // read.columns: text input's column layout
  WriteOptions write;  // ascii, big_endian (PLY)
  std::string format;  // ply | xyz | off | splk, or empty: OUT's extension
};

// Throws Error(kUsage) for bad options or paths, Error(kUnsupported) for an output format it
// cannot write (before reading), Error(kBadInput), Error(kOutput), Error(kOutOfMemory).
StageSummary run_splat_convert(const SplatConvertOptions& options,
                               const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
