// What splat-info tells about a QSplat .qs file: fragments, levels, nodes, leaves, bytes per
// leaf, colour or not, the root sphere and the comment text.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "formats/read_qsplat.h"

namespace splatkit {

// {"file", "format": "qs", "version": 11, "bytes", "tree_fragments", "comment_fragments",
//  "levels", "nodes", "leaves", "interior_nodes", "bytes_per_leaf", "color", "root": {"centre",
//  "radius"}, "comments"}
nlohmann::json describe_qsplat(const QSplatModel& model, const std::string& path);

// The report of describe_qsplat as text, one fact per line.
std::string describe_qsplat_text(const nlohmann::json& report);

}  // namespace splatkit
