// segment-surfaces' work, callable without the command line: read a .splk from build-splat-graph
// (GRPH, CLAS and CLIP chunks), split the splats into smooth surfaces (graph/segment_surfaces.h,
// graph/segment_surfaces_robust.h), drop the small ones (graph/drop_small_surfaces.h) and write
// .splk with a SURF chunk, or a binary PLY with surface_id and class per vertex; optionally a
// JSON report.
#pragma once

#include <cstdint>
#include <string>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "graph/segment_surfaces_robust.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct SegmentSurfacesOptions {
  StagePaths paths;                    // OUT: .splk, .ply or "-" (.splk)
  uint32_t min_size = 1;               // surfaces with fewer splats get kNoSurface (>= 1)
  std::string method = "robust";       // robust | components
  graph::RobustSegmentOptions robust;  // core_threshold, min_core_size; the sharp threshold is
                                       // the graph's own
};

// Throws Error(kUsage) for bad options or paths (before reading), Error(kBadInput) for input that
// is not splats (check_splats.h), lacks the graph chunks, holds one of them twice or holds a
// malformed one (GRPH, CLAS, CLIP and SURF are all decoded), Error(kOutput), Error(kOutOfMemory).
StageSummary run_segment_surfaces(const SegmentSurfacesOptions& options,
                                  const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
