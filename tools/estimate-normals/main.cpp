// estimate-normals: turn a raw point cloud (any input format) into splats — x y z nx ny nz radius,
// colours and extra attributes carried through. The work is splatkit::estimate_normals
// (lib/normals/estimate_normals.h); this file parses arguments, reads, writes and reports.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string_view>

#include "formats/provenance.h"
#include "formats/read_cloud.h"
#include "formats/splk.h"
#include "formats/write_cloud.h"
#include "normals/estimate_normals.h"
#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/progress.h"
#include "splatkit/seconds_since.h"
#include "splatkit/tool.h"

namespace {

using splatkit::Clock;
using splatkit::seconds_since;

std::array<double, 3> parse_viewpoint(const std::string& text) {
  std::array<double, 3> v{};
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0;
  in >> v[0] >> comma1 >> v[1] >> comma2 >> v[2];
  if (!in || comma1 != ',' || comma2 != ',' || !(in >> std::ws).eof() ||
      !std::all_of(v.begin(), v.end(), [](double c) { return std::isfinite(c); }))
    splatkit::throw_usage("--viewpoint must be three finite numbers x,y,z, got '" + text + "'");
  return v;
}

// The output format: --format, else OUT's extension (.ply, .splk), else .splk for '-'.
splatkit::FileFormat output_format(const std::string& output, const std::string& format) {
  if (format == "ply") return splatkit::FileFormat::kPly;
  if (format == "splk") return splatkit::FileFormat::kSplk;
  if (output == "-") return splatkit::FileFormat::kSplk;
  const splatkit::FileFormat f = splatkit::output_format_for(output);
  const bool splk_name = std::string_view(output).ends_with(".splk");
  if (f == splatkit::FileFormat::kPly || splk_name) return f;
  splatkit::throw_usage("OUT must end in .ply or .splk, or be '-' (or give --format ply|splk): " +
                        output);
}

nlohmann::json provenance_options(const splatkit::NormalOptions& o) {
  nlohmann::json j = {{"k", o.k},
                      {"radius_k", o.radius_k},
                      {"radius_scale", o.radius_scale},
                      {"method", splatkit::method_name(o.method)},
                      {"orient", splatkit::orientation_name(o.orient)},
                      {"keep_duplicates", o.keep_duplicates}};
  if (o.viewpoint) j["viewpoint"] = *o.viewpoint;
  return j;
}

void write_report(const std::string& path, nlohmann::json report) {
  splatkit::OutputFile out(path);
  out.write(report.dump(2) + "\n");
  out.commit();
}

}  // namespace

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "estimate-normals",
      "Estimate a unit normal and a splat radius for every point of a cloud (any input format): "
      "PCA over the k nearest neighbours (or a crease-preserving robust method), radius = mean "
      "distance to the radius-k nearest neighbours, orientation by a minimum spanning tree or "
      "towards a viewpoint. Exact duplicate points are merged (the first one's colour and "
      "attributes are kept). OUT is .ply (binary) or .splk; '-' writes .splk to stdout.",
      "  $ estimate-normals scan.ply scan.splk\n"
      "  $ estimate-normals scan.las out.ply --orient viewpoint --viewpoint 0,0,1.8\n"
      "  $ estimate-normals part.xyz part.splk --method robust -k 24 --report part.json\n"
      "  $ estimate-normals big.ply - --orient none --threads 2 | splat-info -\n");
  std::string input, output, format, method = "pca", orient = "mst", viewpoint, report_path;
  splatkit::ReadOptions read;
  splatkit::NormalOptions options;
  auto& app = tool.app();
  app.add_option("IN", input, "Input point cloud, any format ('-' = stdin)")->required();
  app.add_option("OUT", output, "Output .ply or .splk ('-' = .splk on stdout)")->required();
  app.add_option("-k", options.k, "Points per PCA neighbourhood, the point included")
      ->default_val(16)
      ->check(CLI::Range(std::size_t{3}, std::size_t{1024}));
  app.add_option("--radius-k", options.radius_k,
                 "Neighbours whose mean distance is the splat radius")
      ->default_val(5)
      ->check(CLI::Range(std::size_t{1}, std::size_t{1024}));
  app.add_option("--radius-scale", options.radius_scale, "Multiply every radius by S")
      ->default_val(1.0f)
      ->check(CLI::PositiveNumber);
  app.add_option("--method", method, "pca, or robust (keeps creases sharp)")
      ->check(CLI::IsMember({"pca", "robust"}))
      ->default_val("pca");
  auto* orient_opt =
      app.add_option(
             "--orient", orient,
             "mst: consistent over a minimum spanning tree, each component's top-most point "
             "facing +z (closed shapes point outward); viewpoint: towards "
             "--viewpoint or the input's scanner position; none: PCA's sign, made "
             "canonical (largest component positive)")
          ->check(CLI::IsMember({"mst", "viewpoint", "none"}))
          ->default_val("mst");
  app.add_option("--viewpoint", viewpoint,
                 "Scanner position x,y,z in file coordinates (implies --orient viewpoint; "
                 "default: the input's own scanner position)");
  app.add_flag("--keep-duplicates", options.keep_duplicates, "Do not merge exact duplicates");
  app.add_option("--format", format, "Output format, overriding OUT's extension")
      ->check(CLI::IsMember({"ply", "splk"}));
  app.add_option("--columns", read.columns,
                 "Column layout of text input, e.g. x,y,z,r,g,b ('_' skips)");
  app.add_option("--report", report_path, "Write counts, timings and peak RSS as JSON here");
  tool.add_threads_option();

  return tool.run(argc, argv, [&] {
    const Clock::time_point start = Clock::now();
    splatkit::WriteOptions write;
    write.format = output_format(output, format);
    options.method =
        method == "robust" ? splatkit::NormalMethod::kRobust : splatkit::NormalMethod::kPca;
    if (!viewpoint.empty()) {
      if (orient_opt->count() > 0 && orient != "viewpoint")
        splatkit::throw_usage("--viewpoint conflicts with --orient " + orient);
      orient = "viewpoint";
      options.viewpoint = parse_viewpoint(viewpoint);
    }
    options.orient = orient == "viewpoint" ? splatkit::NormalOrientation::kViewpoint
                     : orient == "none"    ? splatkit::NormalOrientation::kNone
                                           : splatkit::NormalOrientation::kMst;
    if (!report_path.empty() && report_path == output)
      splatkit::throw_usage("--report must not be OUT");

    splatkit::Progress progress(tool.name(), tool.quiet() || output == "-");
    Clock::time_point t0 = Clock::now();
    splatkit::InputStream in(input);
    splatkit::LoadedCloud doc = splatkit::read_cloud(in, read);
    const double read_s = seconds_since(t0);

    const splatkit::NormalReport result =
        splatkit::estimate_normals(doc.cloud, options, progress.callback());

    t0 = Clock::now();
    // Chunks that index the splats (a neighbour graph, ...) no longer match the new splats.
    std::erase_if(doc.chunks, [](const splatkit::RawChunk& c) {
      return (c.flags & splatkit::kSplkChunkTiedToSplats) != 0;
    });
    doc.metadata =
        splatkit::make_provenance(tool.name(), provenance_options(options), in, doc, doc.cloud);
    splatkit::write_cloud(doc, output, write);
    const double write_s = seconds_since(t0);

    if (!report_path.empty()) {
      nlohmann::json report = result.to_json();
      report["tool"] = tool.name();
      report["input"] = splatkit::display_name(input);
      report["output"] = splatkit::display_name(output, true);
      report["options"] = provenance_options(options);
      report["threads"] = tool.threads();
      report["timings_s"]["read"] = read_s;
      report["timings_s"]["write"] = write_s;
      report["timings_s"]["command"] = seconds_since(start);
      const uint64_t rss = splatkit::peak_rss_bytes();
      report["peak_rss_bytes"] = rss;
      report["peak_rss_bytes_per_point"] =
          result.input_points > 0 ? static_cast<double>(rss) / result.input_points : 0.0;
      write_report(report_path, report);
    }
    std::string extra = std::to_string(result.duplicates_merged) + " duplicates merged, " +
                        std::to_string(result.degenerate_points) + " degenerate";
    progress.finish(doc.cloud.size(), "points", extra);
  });
}
