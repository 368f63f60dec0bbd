// The robust segmentation's own options (segment_surfaces_robust), which build-splat-graph
// (--surfaces robust, to group the clip partners) and segment-surfaces (--method robust) share:
// --core and --min-core, and how they are recorded in the provenance.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>

#include "graph/segment_surfaces_robust.h"

namespace splatkit::tools {

inline void add_robust_options(CLI::App& app, graph::RobustSegmentOptions& o) {
  app.add_option("--core", o.core_threshold,
                 "robust: n_i.n_j a core splat's continuous neighbours reach at least "
                 "(default: automatic, the cosine of half the sharp angle when the normals are "
                 "noisy, else the sharp threshold itself)")
      ->check(CLI::Range(-1.0f, 1.0f));
  app.add_option("--min-core", o.min_core_size,
                 "robust: core components with fewer splats are not cores")
      ->default_val(10)
      ->check(CLI::Range(uint32_t{1}, uint32_t{0xFFFFFFFEu}));
}

// Adds "core" ("auto" or the threshold) and "min_core" to a tool's provenance options.
inline void put_robust_options(nlohmann::json& options, const graph::RobustSegmentOptions& o) {
  options["core"] = o.core_threshold ? nlohmann::json(*o.core_threshold) : nlohmann::json("auto");
  options["min_core"] = o.min_core_size;
}

}  // namespace splatkit::tools
