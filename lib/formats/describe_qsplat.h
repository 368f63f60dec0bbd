// What splat-info tells about a QSplat .qs file: fragments, levels, nodes, leaves, bytes per
// leaf, colour or not, the root sphere and the comment text.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <string>

#include "formats/read_qsplat.h"

namespace splatkit {

// {"file", "format": "qs", "version": 11, "bytes", "tree_fragments", "comment_fragments",
//  "levels", "nodes", "leaves", "interior_nodes", "bytes_per_leaf", "color", "root": {"centre",
//  "radius"}, "origin" (when qsplat_origin is not zero), "comments"}, and the keys every report
// has (formats/describe_common.h): "entries" (= "nodes"), "bounds" (the box of the root spheres,
// origin added back), "crs" (null)
nlohmann::json describe_qsplat(const QSplatModel& model, const std::string& path);

// The offset from the file's local frame to the coordinates of the cloud it was made from, which
// build-qsplat records as "origin" in the JSON of its "splatkit {...}" comment line, the last
// (the v11 spheres are float32: a georeferenced cloud is written near zero). Zero when that line
// gives no three finite numbers.
std::array<double, 3> qsplat_origin(const QSplatModel& model);

// The sphere build-qsplat records as "view_sphere": {"centre": [x, y, z], "radius": r} in the same
// JSON: the sphere a camera frames the input splats by (render/splat_bounds.h), in the file's
// local frame, computed on the splats before quantisation (the decoded leaves are larger than
// the splats, by up to several times for a few). Returned as {x, y, z, r}; nullopt when the line
// is missing, or gives no finite centre or no positive finite radius (older files).
std::optional<std::array<float, 4>> qsplat_view_sphere(const QSplatModel& model);

// The box build-qsplat records beside it as "view_box": {"min": [x, y, z], "max": [x, y, z]}: the
// splats' reach (centre +- radius per axis) before quantisation, which default views fill the
// frame with. Returned as {min x, y, z, max x, y, z}; nullopt when missing or not finite and
// ordered (older files).
std::optional<std::array<float, 6>> qsplat_view_box(const QSplatModel& model);

// The report of describe_qsplat as text, one fact per line.
std::string describe_qsplat_text(const nlohmann::json& report);

}  // namespace splatkit
