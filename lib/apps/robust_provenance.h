// How build-splat-graph (--surfaces robust) and segment-surfaces (--method robust) record the
// robust segmentation's options (graph/segment_surfaces_robust.h) in their provenance and report.
#pragma once

#include <nlohmann/json.hpp>

#include "graph/segment_surfaces_robust.h"

namespace splatkit::apps {

// Adds "core" ("auto" or the threshold) and "min_core" to `options`.
inline void put_robust_options(nlohmann::json& options, const graph::RobustSegmentOptions& o) {
  options["core"] = o.core_threshold ? nlohmann::json(*o.core_threshold) : nlohmann::json("auto");
  options["min_core"] = o.min_core_size;
}

}  // namespace splatkit::apps
