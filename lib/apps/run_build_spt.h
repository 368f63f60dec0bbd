// build-spt's work, callable without the command line: read splats (normals and radii), build the
// Sequential Point Tree [Dachsbacher03] (spt/build_spt_tree.h), sequentialise and quantise its
// list (spt/encode_spt.h) and write the .spt file (formats/spt.md), optionally with a JSON report.
#pragma once

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "formats/read_cloud.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct BuildSptOptions {
  StagePaths paths;        // OUT: .spt or "-"
  ReadOptions read;        // read.columns: text input's column layout
  float epsilon = 1e-3f;   // screen error (radians) the stored r values are stated for, > 0
  float color_weight = 1;  // L: weight of the colour deviation in the error, >= 0
  bool full = false;       // --precision full: 40-byte float entries
  // --max-memory: the tool's frame spills the large arrays to --tmp-dir
  // (splatkit/spill_arena.h); the passes run through them in Morton order.
  MemoryLimit memory;
};

// Throws Error(kUsage) for bad paths or options (before reading), Error(kBadInput) for splats
// without normals or radii (naming estimate-normals), unusable splats (check_splats.h) or
// unreadable input, Error(kUnsupported) for an empty cloud or one of 2^31 points or more,
// Error(kOutput), Error(kOutOfMemory).
StageSummary run_build_spt(const BuildSptOptions& options,
                           const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
