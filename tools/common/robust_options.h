// The robust segmentation's options (graph/segment_surfaces_robust.h) that build-splat-graph
// (--surfaces robust, to group the clip partners) and segment-surfaces (--method robust) share:
// --core and --min-core. Their provenance: apps/robust_provenance.h.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>

#include "graph/segment_surfaces_robust.h"
#include "splatkit/tool.h"

namespace splatkit::tools {

inline void add_robust_options(CLI::App& app, graph::RobustSegmentOptions& o) {
  app.add_option("--core", o.core_threshold,
                 "robust: n_i.n_j a core splat's continuous neighbours reach at least "
                 "(default: automatic, the cosine of half the sharp angle when the normals are "
                 "noisy or when half the sharp edges lie inside components of the continuous "
                 "edges, else the sharp threshold itself)")
      ->check(finite_range(-1.0, 1.0));
  app.add_option("--min-core", o.min_core_size,
                 "robust: core components with fewer splats are not cores")
      ->default_val(10)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
}

}  // namespace splatkit::tools
