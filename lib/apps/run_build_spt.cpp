#include "apps/run_build_spt.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <sstream>
#include <string_view>

#include "splatkit/check_splats.h"
#include "splatkit/error.h"
#include "spt/build_spt_tree.h"
#include "spt/encode_spt.h"

namespace splatkit::apps {

namespace {

// v[i] = v[order[i]], one array at a time (so the extra memory is one array's).
template <class T>
void permute(std::vector<T>& v, const std::vector<uint32_t>& order) {
  if (v.empty()) return;
  std::vector<T> out(v.size());
  tbb::parallel_for(std::size_t{0}, v.size(), [&](std::size_t i) { out[i] = v[order[i]]; });
  v.swap(out);
}

}  // namespace

StageSummary run_build_spt(const BuildSptOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (output != "-" && !std::string_view(output).ends_with(".spt"))
    throw_usage("OUT must end in .spt or be '-': " + output);
  if (!(o.epsilon > 0) || !std::isfinite(o.epsilon))
    throw_usage("--epsilon must be a positive number of radians");
  if (!(o.color_weight >= 0) || !std::isfinite(o.color_weight))
    throw_usage("--color-weight must be zero or positive");
  Stage stage("build-spt", o.paths);
  LoadedCloud doc = stage.read(o.read, progress);
  SplatCloud& cloud = doc.cloud;
  if (cloud.size() == 0) throw_unsupported(stage.input_name(), "no points");
  if (cloud.size() >= (std::size_t{1} << 31))
    throw_unsupported(stage.input_name(), "2^31 points or more");
  check_splats(cloud, stage.input_name());
  cloud.extras = {};  // not part of an .spt: the memory goes to the tree
  cloud.axes = {};
  cloud.minor_radii = {};
  for (Vec3f& n : cloud.normals) n = normalized(n);
  // The splats in the tree's order: building and encoding then read memory in order.
  stage.phase("order", "sorting the splats", [&] {
    const std::vector<uint32_t> order = spt::morton_order(cloud.positions);
    permute(cloud.positions, order);
    permute(cloud.normals, order);
    permute(cloud.radii, order);
    permute(cloud.colors, order);
  });
  const spt::SptInput input{cloud.positions, cloud.normals, cloud.radii, cloud.colors,
                            cloud.color_bits};
  progress(0.3, "building the tree");
  const spt::SptTree tree = stage.phase("tree", "building the point tree",
                                        [&] { return spt::build_spt_tree(input, o.color_weight); });
  const nlohmann::json options = {{"epsilon", o.epsilon},
                                  {"color_weight", o.color_weight},
                                  {"precision", o.full ? "full" : "compact"}};
  stage.stamp(doc, options);
  progress(0.7, "sequentialising");
  spt::EncodeSptOptions eo;
  eo.epsilon = o.epsilon;
  eo.color_weight = o.color_weight;
  eo.full = o.full;
  eo.origin = cloud.origin;
  spt::EncodedSpt file = stage.phase("sequentialise", "sorting and quantising the list",
                                     [&] { return spt::encode_spt(tree, input, eo); });
  const Clock::time_point t0 = Clock::now();
  OutputFile out(output);
  out.write(file.bytes.data(), file.bytes.size());
  stage.record("write", seconds_since(t0));

  nlohmann::json report;
  const double n = static_cast<double>(cloud.size());
  if (!o.paths.report.empty()) {
    report = {{"input_points", cloud.size()},
              {"tree_nodes", tree.size()},
              {"interior_nodes", tree.interiors.size()},
              {"entries", file.entries},
              {"entries_dropped_empty_interval", file.dropped_empty},
              {"entries_per_input_point", static_cast<double>(file.entries) / n},
              {"depth", tree.depth},
              {"precision", o.full ? "full" : "compact"},
              {"color", !cloud.colors.empty()},
              {"file_bytes", file.bytes.size()},
              {"bytes_per_input_point", static_cast<double>(file.bytes.size()) / n},
              {"peak_rss_bytes_per_point", static_cast<double>(peak_rss_bytes()) / n}};
    const double work = stage.seconds("read") + stage.seconds("order") + stage.seconds("tree") +
                        stage.seconds("sequentialise") + stage.seconds("write");
    if (work > 0) report["points_per_second"] = std::round(n / work);
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  std::ostringstream extra;
  extra << file.entries << " entries (" << static_cast<double>(file.entries) / n
        << " per point), depth " << tree.depth << ", " << file.bytes.size() << " bytes";
  return {cloud.size(), "points", extra.str()};
}

}  // namespace splatkit::apps
