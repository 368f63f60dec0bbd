#include "apps/run_merge_spt.h"

#include <sstream>

#include "apps/merge_inputs.h"
#include "formats/read_spt.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "spt/merge_spt.h"

namespace splatkit::apps {

StageSummary run_merge_spt(const MergeSptOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "spt")
    throw_usage("OUT must end in .spt or be '-': " + output);
  check_merge_inputs(o.paths, o.more_inputs);
  Stage stage("build-spt", o.paths);
  progress(0.0, "reading the tiles");
  std::vector<std::string> names;
  const std::vector<SptModel> tiles = read_merge_inputs<SptModel>(
      stage, o.more_inputs, names, [](InputStream& in) { return read_spt(in); });
  progress(0.5, "merging");
  const spt::MergedSpt merged = merge_phase(stage, "merge", "merging the lists",
                                            [&] { return spt::merge_spt(tiles, names); });
  const Clock::time_point t0 = Clock::now();
  OutputFile out(output);
  out.write(merged.bytes.data(), merged.bytes.size());
  stage.record("write", seconds_since(t0));
  uint64_t points = 0;
  for (const SptModel& m : tiles) points += m.header.input_points;
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    nlohmann::json inputs = nlohmann::json::array();
    for (std::size_t t = 0; t < tiles.size(); ++t)
      inputs.push_back({{"name", names[t]},
                        {"entries", tiles[t].size()},
                        {"input_points", tiles[t].header.input_points}});
    report = {{"merge", true},
              {"inputs", inputs},
              {"input_points", points},
              {"entries", merged.entries},
              {"new_nodes", merged.new_nodes},
              {"entries_dropped_empty_interval", merged.dropped_empty},
              {"depth", merged.depth},
              {"file_bytes", merged.bytes.size()}};
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  std::ostringstream extra;
  extra << tiles.size() << " tiles merged, " << merged.entries << " entries (" << merged.new_nodes
        << " new above the tiles), depth " << merged.depth << ", " << merged.bytes.size()
        << " bytes";
  return {points, "points", extra.str()};
}

}  // namespace splatkit::apps
