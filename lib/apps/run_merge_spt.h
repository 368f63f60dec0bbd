// build-spt --merge: one .spt list from the .spt lists of tiles (spt/merge_spt.h; the tiles built
// each from its own points by build-spt), written as build-spt writes, with an optional JSON
// report.
#pragma once

#include <string>
#include <vector>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct MergeSptOptions {
  StagePaths paths;                      // IN: the first tile's .spt; OUT: .spt or "-"
  std::vector<std::string> more_inputs;  // the other tiles' .spt files
};

// Throws Error(kUsage) for bad paths (before reading), Error(kBadInput) naming the file for a
// file that is not a valid .spt or that cannot join the first (merge_spt.h), Error(kUnsupported)
// for a newer .spt version, Error(kOutput), Error(kOutOfMemory).
StageSummary run_merge_spt(const MergeSptOptions& options,
                           const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
