// build-qsplat --merge: one .qs tree from the .qs trees of tiles (qsplat/merge_qsplat.h; the
// tiles built each from its own points by build-qsplat), written as build-qsplat writes, with an
// optional JSON report.
#pragma once

#include <string>
#include <vector>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct MergeQSplatOptions {
  StagePaths paths;                      // IN: the first tile's .qs; OUT: .qs or "-"
  std::vector<std::string> more_inputs;  // the other tiles' .qs files
};

// Throws Error(kUsage) for bad paths (before reading), Error(kBadInput) naming the file for a
// file that is not a valid .qs or cannot join the first (merge_qsplat.h), Error(kUnsupported)
// for a tree beyond one fragment, Error(kOutput), Error(kOutOfMemory).
StageSummary run_merge_qsplat(const MergeQSplatOptions& options,
                              const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
