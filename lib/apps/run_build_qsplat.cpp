#include "apps/run_build_qsplat.h"

#include <sstream>
#include <string_view>

#include "qsplat/build_qsplat_tree.h"
#include "qsplat/encode_qsplat.h"
#include "qsplat/make_qsplat_leaves.h"
#include "render/splat_bounds.h"
#include "splatkit/drop_halo_points.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"

namespace splatkit::apps {

namespace {

// The comment fragment: the input's PLY comments, a line each without the keyword as the
// original qsplat_make stores them, then this run's provenance with the sphere a camera frames
// the leaves by (describe_qsplat.h's qsplat_view_sphere).
std::string comment_text(const LoadedCloud& doc, const render::BoundingSphere& view) {
  std::string text;
  const auto it = doc.header.find("comments");
  if (it != doc.header.end() && it->is_array())
    for (const auto& c : *it)
      if (c.is_string()) text += c.get<std::string>() + "\n";
  nlohmann::json meta = doc.metadata;
  // The spheres are in the cloud's local frame (float32 holds georeferenced coordinates only to
  // metres): where that frame sits, for splat-view's cameras in file coordinates.
  if (doc.cloud.origin != std::array<double, 3>{0, 0, 0}) meta["origin"] = doc.cloud.origin;
  meta["view_sphere"] = {{"centre", {view.center.x, view.center.y, view.center.z}},
                         {"radius", view.radius}};
  if (view.has_box())
    meta["view_box"] = {{"min", {view.box_lo.x, view.box_lo.y, view.box_lo.z}},
                        {"max", {view.box_hi.x, view.box_hi.y, view.box_hi.z}}};
  text += "splatkit " + meta.dump() + "\n";
  return text;
}

}  // namespace

StageSummary run_build_qsplat(const BuildQSplatOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "qs")
    throw_usage("OUT must end in .qs or be '-': " + output);
  Stage stage("build-qsplat", o.paths);
  LoadedCloud doc = stage.read(o.read, progress);
  // A tile of splat-tile: its own points only (its halo belongs to its neighbours' files).
  drop_halo_points(doc.cloud, stage.input_name());
  const nlohmann::json options = {{"no_color", o.no_color}, {"centroid_rule", o.centroid_rule}};
  stage.stamp(doc, options);  // provenance from the input cloud, before the leaves take it over
  const std::size_t input_points = doc.cloud.size(), input_faces = doc.cloud.face_count();
  if (o.no_color) doc.cloud.colors.clear();
  qsplat::QSplatLeaves leaves = stage.phase("leaves", "collecting the leaves", [&] {
    return qsplat::make_qsplat_leaves(std::move(doc.cloud), stage.input_name());
  });
  if (leaves.size() < 5)
    throw_unsupported(stage.input_name(),
                      std::to_string(leaves.size()) +
                          " usable points; a QSplat file needs at least 5 (the original viewer "
                          "cannot read a tree of 4 leaves or fewer)");
  qsplat::QSplatTree tree = stage.phase("tree", "building the QSplat tree", [&] {
    return qsplat::build_qsplat_tree(leaves, o.centroid_rule, !o.paths.report.empty());
  });
  // Framed by the splats themselves: the decoded leaves differ from them (the cell nearest each
  // splat's disc, a few several times larger), which would frame the model unlike the plain
  // render of the same cloud.
  const render::BoundingSphere view =
      render::splat_bounds(leaves.size(), [&](std::size_t i, Vec3f& c, float& r) {
        c = leaves.positions[i];
        r = leaves.radii[i];
        return true;
      });
  // The input's arrays are done with: freed before the encoder's are made (the counts stay).
  const bool color = !leaves.colors.empty();
  { const qsplat::QSplatLeaves done = std::move(leaves); }
  qsplat::EncodedQSplat file = stage.phase("quantise", "quantising the QSplat tree", [&] {
    try {
      return qsplat::encode_qsplat(tree, comment_text(doc, view));
    } catch (const Error& e) {  // input that the format cannot hold: named as such
      if (e.kind() == ErrorKind::kBadInput) throw_bad_input(stage.input_name(), e.what());
      throw;
    }
  });
  const Clock::time_point t0 = Clock::now();
  OutputFile out(output);
  out.write(file.bytes.data(), file.bytes.size());
  stage.record("write", seconds_since(t0));

  nlohmann::json report;
  if (!o.paths.report.empty()) {
    const double n = static_cast<double>(file.leaves);
    report = {{"input_points", input_points},
              {"input_faces", input_faces},
              {"leaves", file.leaves},
              {"dropped_unused", leaves.dropped_unused},
              {"dropped_zero_radius", leaves.dropped_zero_radius},
              {"dropped_zero_normal", leaves.dropped_zero_normal},
              {"nodes", tree.size() - 1},  // the file's (the root is in the header)
              {"levels", tree.levels() - 1},
              {"color", color},
              {"file_bytes", file.bytes.size()},
              {"tree_bytes", file.tree_bytes},
              {"bytes_per_leaf", static_cast<double>(file.bytes.size()) / n},
              {"tree_bytes_per_leaf", static_cast<double>(file.tree_bytes) / n},
              {"sphere_rule", o.centroid_rule ? "centroid" : "tight"},
              {"mean_interior_radius", tree.mean_interior_radius},
              {"leaf_radius_growth_mean", file.leaf_growth_mean},
              {"leaf_radius_growth_max", file.leaf_growth_max},
              {"mean_interior_radius_centroid_rule", tree.mean_interior_radius_centroid},
              {"tight_over_centroid_radius",
               tree.mean_interior_radius / tree.mean_interior_radius_centroid}};
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  const uint64_t dropped =
      leaves.dropped_unused + leaves.dropped_zero_radius + leaves.dropped_zero_normal;
  std::ostringstream extra;
  extra << tree.size() - 1 << " nodes, " << tree.levels() - 1 << " levels, " << file.bytes.size()
        << " bytes (" << static_cast<double>(file.bytes.size()) / static_cast<double>(file.leaves)
        << " per leaf)";
  if (dropped > 0) extra << ", " << dropped << " points dropped";
  return {file.leaves, "points", extra.str()};  // the points kept, one leaf each
}

}  // namespace splatkit::apps
