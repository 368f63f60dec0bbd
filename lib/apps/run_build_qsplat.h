// build-qsplat's work, callable without the command line: read splats (normals and radii) or a
// triangle mesh, build the QSplat bounding-sphere tree (qsplat/build_qsplat_tree.h) and write the
// .qs v11 file (qsplat/encode_qsplat.h, formats/qsplat.md), optionally with a JSON report.
#pragma once

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "formats/read_cloud.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct BuildQSplatOptions {
  StagePaths paths;            // OUT: .qs or "-"
  ReadOptions read;            // read.columns: text input's column layout
  bool no_color = false;       // drop the colours (4-byte nodes)
  bool centroid_rule = false;  // the original's node spheres (centroid + farthest) instead of tight
};

// Throws Error(kUsage) for bad paths (before reading), Error(kBadInput) for splats without normals
// or radii (naming estimate-normals) or unreadable input, Error(kUnsupported) for fewer than 5
// kept points or a tree beyond one fragment, Error(kOutput), Error(kOutOfMemory).
StageSummary run_build_qsplat(const BuildQSplatOptions& options,
                              const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
