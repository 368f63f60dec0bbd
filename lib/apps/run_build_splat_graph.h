// build-splat-graph's work, callable without the command line: read splats (normals and radii),
// build the splat graph (graph/build_splat_graph.h) and write .splk with the chunks GRPH, CLAS
// and CLIP (graph_io/graph_chunks.h), and optionally a JSON report.
#pragma once

#include <string>

#include "apps/stage.h"
#include "apps/stage_types.h"
#include "graph/build_splat_graph.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct BuildSplatGraphOptions {
  StagePaths paths;  // OUT: .splk or "-"
  graph::SplatGraphOptions graph;
  std::string surfaces = "robust";  // robust | components: sets graph.robust_surfaces
};

// Throws Error(kUsage) for bad options or paths (before reading), Error(kBadInput) for input
// that is not splats (check_splats.h) or is unreadable, Error(kOutput), Error(kOutOfMemory).
StageSummary run_build_splat_graph(const BuildSplatGraphOptions& options,
                                   const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
