// What splat-info tells about a Sequential Point Tree .spt file: version, precision, entries,
// leaves, input points, depth, bytes per entry, colour, the build's epsilon and colour weight,
// the r range and the quantisation frame.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "formats/read_spt.h"

namespace splatkit {

// {"file", "format": "spt", "version", "bytes", "precision": "compact"|"full", "entry_bytes",
//  "entries", "leaves", "interior_entries", "input_points", "depth", "entries_per_input_point",
//  "color", "epsilon", "color_weight", "r_range": [lo, hi], "origin", "quantisation_step"}, and the keys every
// report has (formats/describe_common.h): "bounds" (the box of the leaves' centres, origin added
// back), "crs" (null)
nlohmann::json describe_spt(const SptModel& model, const std::string& path);

// The report of describe_spt as text, one fact per line.
std::string describe_spt_text(const nlohmann::json& report);

}  // namespace splatkit
