// What splat-info tells about a QSplat .qs file: fragments, levels, nodes, leaves, bytes per
// leaf, colour or not, the root sphere and the comment text.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <string>

#include "formats/read_qsplat.h"

namespace splatkit {

// {"file", "format": "qs", "version": 11, "bytes", "tree_fragments", "comment_fragments",
//  "levels", "nodes", "leaves", "interior_nodes", "bytes_per_leaf", "color", "root": {"centre",
//  "radius"}, "origin" (when qsplat_origin is not zero), "comments"}
nlohmann::json describe_qsplat(const QSplatModel& model, const std::string& path);

// The offset from the file's local frame to the coordinates of the cloud it was made from, which
// build-qsplat records as "origin" in the JSON of its "splatkit {...}" comment line, the last
// (the v11 spheres are float32: a georeferenced cloud is written near zero). Zero when that line
// gives no three finite numbers.
std::array<double, 3> qsplat_origin(const QSplatModel& model);

// The report of describe_qsplat as text, one fact per line.
std::string describe_qsplat_text(const nlohmann::json& report);

}  // namespace splatkit
