// segment-surfaces' work, callable without the command line: read a .splk from build-splat-graph
// (GRPH, CLAS and CLIP chunks), split the splats into smooth surfaces (graph/segment_surfaces.h,
// graph/segment_surfaces_robust.h), move the border splats to the surface whose fitted geometry
// explains them (graph/refine_surface_borders.h), merge the fragments into their neighbours
// (graph/merge_small_surfaces.h), split off and join surfaces by their fitted planes
// (graph/split_planar_surfaces.h, graph/merge_coplanar_surfaces.h), drop the small surfaces
// (graph/drop_small_surfaces.h) and write .splk with a SURF chunk, or a binary PLY with surface_id
// and class per vertex; optionally a JSON report.
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
  uint32_t refine_rounds = 8;          // refine_surface_borders' rounds (0: no refinement)
  uint32_t merge_below = 50;           // surfaces with fewer splats are fragments: refined splat
                                       // by splat, the rest merged by shared edges (1: none)
  double coplanar_scales = 3;          // planar surfaces give up pieces off their plane beyond
                                       // this many robust scales (split_planar_surfaces) and take
                                       // surfaces within them (merge_coplanar_surfaces); 0: none
};

// Throws Error(kUsage) for bad options or paths (before reading), Error(kBadInput) for input that
// is not splats (check_splats.h), lacks the graph chunks, holds one of them twice or holds a
// malformed one (GRPH, CLAS, CLIP and SURF are all decoded), Error(kOutput), Error(kOutOfMemory).
StageSummary run_segment_surfaces(const SegmentSurfacesOptions& options,
                                  const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
