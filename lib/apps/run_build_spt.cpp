#include "apps/run_build_spt.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <optional>
#include <sstream>
#include <string_view>

#include "apps/tile_survey_box.h"
#include "splatkit/check_splats.h"
#include "splatkit/drop_halo_points.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/spill_arena.h"
#include "splatkit/take_own_points.h"
#include "spt/build_spt_tree.h"
#include "spt/encode_spt.h"

namespace splatkit::apps {

namespace {
// The spill file's peak per point with --max-memory, with a margin: 57 bytes per point measured on
// a 200M-point torus under a 2G limit (scripts/bench/scale.sh).
constexpr std::size_t kSpillBytesPerPoint = 80;
}  // namespace

StageSummary run_build_spt(const BuildSptOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "spt")
    throw_usage("OUT must end in .spt or be '-': " + output);
  // (the options are floats: 1e300 arrives as inf)
  if (!(o.epsilon > 0) || !std::isfinite(o.epsilon))
    throw_usage("--epsilon must be a positive number of radians within float range, got " +
                std::to_string(o.epsilon));
  if (!(o.color_weight >= 0) || !std::isfinite(o.color_weight))
    throw_usage("--color-weight must be zero or positive and within float range, got " +
                std::to_string(o.color_weight));
  Stage stage("build-spt", o.paths);
  LoadedCloud doc = stage.read(o.read, progress);
  spill::check_room(doc.cloud.size() * kSpillBytesPerPoint);
  SplatCloud& cloud = doc.cloud;
  // A tile of splat-tile: its own points only (its halo belongs to its neighbours' files).
  const bool is_tile = cloud.find_extra(kHaloAttribute) != nullptr;
  drop_halo_points(cloud, stage.input_name());
  if (cloud.size() == 0) throw_bad_input(stage.input_name(), "the file has no points");
  if (cloud.size() >= (std::size_t{1} << 31))
    throw_unsupported(stage.input_name(), "2^31 points or more");
  check_splats(cloud, stage.input_name());
  // A tile's octree in the survey's Morton cube, its positions coded over the survey's box: the
  // whole build's cells and frame (docs/design/tiles.md, "Merged level-of-detail files").
  const std::optional<Bounds> survey =
      is_tile ? tile_survey_box(doc.metadata, cloud.origin, compute_bounds(cloud.positions))
              : std::nullopt;
  // Not part of an .spt: the memory goes to the tree (swapped out: `= {}` keeps the capacity).
  std::vector<ExtraAttribute>().swap(cloud.extras);
  std::vector<Vec3f>().swap(cloud.axes);
  std::vector<float>().swap(cloud.minor_radii);
  const std::size_t points = cloud.size();
  const bool has_color = !cloud.colors.empty();
  // The splats in the tree's order, moved out of the cloud (colours made 8-bit).
  spt::SptSplats splats = spt::take_spt_splats(cloud);
  spt::SptOrder order = stage.phase("order", "sorting the splats", [&] {
    return spt::sort_spt_splats(splats, nullptr, survey ? &*survey : nullptr);
  });
  progress(0.3, "building the tree");
  spt::SptTree tree = stage.phase("tree", "building the point tree", [&] {
    return spt::build_spt_tree(splats, order, {o.color_weight, o.full});
  });
  std::vector<uint8_t>().swap(order.levels);
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
  // Written as encoded: the list is never whole in memory when the output can be patched (a
  // file: encoded in place, the header written at the end).
  OutputFile out(output);
  spt::SptSink sink;
  sink.write = [&](const unsigned char* p, std::size_t k) { out.write(p, k); };
  if (!out.is_direct()) {
    sink.patch = [&](uint64_t at, const unsigned char* p, std::size_t k) {
      out.write_at(at, p, k);
    };
    sink.reserve = [&](uint64_t total) { return out.reserve(total); };
    sink.write_through = [&](uint64_t at, const unsigned char* p, std::size_t k) {
      out.write_through(at, p, k);
    };
  }
  const Clock::time_point t0 = Clock::now();
  const spt::EncodedSpt file = spt::encode_spt(tree, splats, eo, sink);
  const double encode_s = seconds_since(t0);
  stage.record("sequentialise", encode_s - file.write_seconds);
  stage.record("write", file.write_seconds);

  nlohmann::json report;
  const double n = static_cast<double>(points);
  if (!o.paths.report.empty()) {
    report = {{"input_points", points},
              {"tree_nodes", tree.size()},
              {"interior_nodes", tree.interiors},
              {"entries", file.entries},
              {"entries_dropped_empty_interval", file.dropped_empty},
              {"entries_per_input_point", static_cast<double>(file.entries) / n},
              {"depth", tree.depth},
              {"precision", o.full ? "full" : "compact"},
              {"color", has_color},
              {"file_bytes", file.bytes},
              {"bytes_per_input_point", static_cast<double>(file.bytes) / n},
              {"peak_rss_bytes_per_point", static_cast<double>(peak_rss_bytes()) / n}};
    if (survey) report["frame"] = "survey_box";
    const double work = stage.seconds("read") + stage.seconds("order") + stage.seconds("tree") +
                        stage.seconds("sequentialise") + stage.seconds("write");
    if (work > 0) report["points_per_second"] = std::round(n / work);
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  std::ostringstream extra;
  extra << file.entries << " entries (" << static_cast<double>(file.entries) / n
        << " per point), depth " << tree.depth << ", " << file.bytes << " bytes";
  return {points, "points", extra.str()};
}

}  // namespace splatkit::apps
