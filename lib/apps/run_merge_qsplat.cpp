#include "apps/run_merge_qsplat.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "apps/merge_inputs.h"
#include "formats/describe_qsplat.h"
#include "formats/provenance.h"
#include "formats/read_qsplat.h"
#include "qsplat/encode_qsplat.h"
#include "qsplat/merge_qsplat.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/version.h"

namespace splatkit::apps {

namespace {

// The comment fragment's provenance line: the inputs, the common origin, and the sphere and box
// splat-view frames the model by. The box is the union of the tiles' (each the reach of its
// splats, so the union is the whole survey's); the sphere is centred on the box and reaches
// every tile's sphere (the survey's own is centred on the box of the splat centres, which the
// tiles do not record: this one may be a little larger). Left out when a tile lacks them.
std::string comment_text(std::span<const QSplatModel> tiles, const std::array<double, 3>& origin,
                         const nlohmann::json& inputs) {
  nlohmann::json meta = {{"tool", "build-qsplat"},
                         {"version", kVersion},
                         {"options", {{"merge", true}}},
                         {"inputs", inputs}};
  if (origin != std::array<double, 3>{0, 0, 0}) meta["origin"] = origin;
  std::array<float, 6> box{3.4e38f, 3.4e38f, 3.4e38f, -3.4e38f, -3.4e38f, -3.4e38f};
  bool framed = true;
  // Tile m's point in the merged frame.
  auto moved = [&](const QSplatModel& m, float x, int a) {
    return static_cast<float>(qsplat_origin(m)[a] - origin[a] + double(x));
  };
  for (const QSplatModel& m : tiles) {
    const auto b = qsplat_view_box(m);
    if (!b || !qsplat_view_sphere(m)) {
      framed = false;
      break;
    }
    for (int a = 0; a < 3; ++a) {
      box[a] = std::min(box[a], moved(m, (*b)[a], a));
      box[3 + a] = std::max(box[3 + a], moved(m, (*b)[3 + a], a));
    }
  }
  if (framed) {
    const Vec3f centre{(box[0] + box[3]) * 0.5f, (box[1] + box[4]) * 0.5f,
                       (box[2] + box[5]) * 0.5f};
    float radius = 0;
    for (const QSplatModel& m : tiles) {
      const auto s = *qsplat_view_sphere(m);
      const Vec3f c{moved(m, s[0], 0), moved(m, s[1], 1), moved(m, s[2], 2)};
      radius = std::max(radius, norm(c - centre) + s[3]);
    }
    meta["view_sphere"] = {{"centre", {centre.x, centre.y, centre.z}}, {"radius", radius}};
    meta["view_box"] = {{"min", {box[0], box[1], box[2]}}, {"max", {box[3], box[4], box[5]}}};
  }
  return "splatkit " + meta.dump() + "\n";
}

}  // namespace

StageSummary run_merge_qsplat(const MergeQSplatOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "qs")
    throw_usage("OUT must end in .qs or be '-': " + output);
  check_merge_inputs(o.paths, o.more_inputs);
  Stage stage("build-qsplat", o.paths);
  progress(0.0, "reading the tiles");
  std::vector<std::string> names;
  nlohmann::json inputs = nlohmann::json::array();
  const std::vector<QSplatModel> tiles =
      read_merge_inputs<QSplatModel>(stage, o.more_inputs, names, [&](InputStream& in) {
        QSplatModel m = read_qsplat(in);
        inputs.push_back(input_record(in, "qs"));
        return m;
      });
  progress(0.3, "merging");
  qsplat::MergedQSplatTree merged = merge_phase(
      stage, "tree", "merging the trees", [&] { return qsplat::merge_qsplat_tree(tiles, names); });
  if (merged.leaves < 5)  // not reached from build-qsplat's tiles (5 leaves each)
    throw_unsupported(names[0], "fewer than 5 leaves in all");
  progress(0.6, "quantising");
  const std::string comments = comment_text(tiles, merged.origin, inputs);
  qsplat::EncodedQSplat file = stage.phase("quantise", "quantising the QSplat tree", [&] {
    return qsplat::encode_qsplat(merged.tree, comments);
  });
  const Clock::time_point t0 = Clock::now();
  OutputFile out(output);
  out.write(file.bytes.data(), file.bytes.size());
  stage.record("write", seconds_since(t0));
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    const double n = static_cast<double>(file.leaves);
    report = {{"merge", true},
              {"inputs", inputs},
              {"leaves", file.leaves},
              {"upper_nodes", merged.upper_nodes},
              {"nodes", merged.tree.size() - 1},
              {"levels", merged.tree.levels() - 1},
              {"color", tiles[0].has_color},
              {"file_bytes", file.bytes.size()},
              {"tree_bytes", file.tree_bytes},
              {"bytes_per_leaf", static_cast<double>(file.bytes.size()) / n},
              {"leaf_radius_growth_mean", file.leaf_growth_mean},
              {"leaf_radius_growth_max", file.leaf_growth_max}};
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  std::ostringstream extra;
  extra << tiles.size() << " tiles merged, " << merged.tree.size() - 1 << " nodes ("
        << merged.upper_nodes << " above the tiles), " << merged.tree.levels() - 1 << " levels, "
        << file.bytes.size() << " bytes";
  return {file.leaves, "points", extra.str()};
}

}  // namespace splatkit::apps
