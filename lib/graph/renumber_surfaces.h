// renumber_surfaces: a Segmentation from arbitrary surface labels, with the ids every segmentation
// here gives — 0.. in the order of each surface's lowest splat index — so the result depends only
// on which splats share a label, never on the label values.
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"

namespace splatkit::graph {

// labels: #N, any values < label_count (throws std::invalid_argument otherwise). O(N +
// label_count).
Segmentation renumber_surfaces(std::span<const uint32_t> labels, uint32_t label_count);

}  // namespace splatkit::graph
