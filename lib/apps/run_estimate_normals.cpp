#include "apps/run_estimate_normals.h"

#include <string_view>

#include "apps/parse_triple.h"
#include "splatkit/error.h"

namespace splatkit::apps {

namespace {

// The output format: --format, else OUT's extension (.ply, .splk), else .splk for '-'.
FileFormat output_format(const std::string& output, const std::string& format) {
  if (format == "ply") return FileFormat::kPly;
  if (format == "splk") return FileFormat::kSplk;
  if (!format.empty()) throw_usage("--format must be ply or splk, got '" + format + "'");
  if (output == "-") return FileFormat::kSplk;
  const FileFormat f = output_format_for(output);
  if (f == FileFormat::kPly || std::string_view(output).ends_with(".splk")) return f;
  throw_usage("OUT must end in .ply or .splk, or be '-' (or give --format ply|splk): " + output);
}

NormalOptions normal_options(const EstimateNormalsOptions& o) {
  NormalOptions n = o.normals;
  if (o.method != "pca" && o.method != "robust")
    throw_usage("--method must be pca or robust, got '" + o.method + "'");
  n.method = o.method == "robust" ? NormalMethod::kRobust : NormalMethod::kPca;
  std::string orient = o.orient.empty() ? "mst" : o.orient;
  if (!o.viewpoint.empty()) {
    if (!o.orient.empty() && o.orient != "viewpoint")
      throw_usage("--viewpoint conflicts with --orient " + o.orient);
    orient = "viewpoint";
    n.viewpoint = parse_triple(o.viewpoint, "--viewpoint");
  }
  if (orient != "mst" && orient != "viewpoint" && orient != "none")
    throw_usage("--orient must be mst, viewpoint or none, got '" + orient + "'");
  n.orient = orient == "viewpoint" ? NormalOrientation::kViewpoint
             : orient == "none"    ? NormalOrientation::kNone
                                   : NormalOrientation::kMst;
  if (!(n.radius_scale > 0) || !std::isfinite(n.radius_scale))
    throw_usage("--radius-scale must be a positive finite number");
  if (o.radius != "cover" && o.radius != "mean-knn")
    throw_usage("--radius must be cover or mean-knn, got '" + o.radius + "'");
  if (o.splat != "circle" && o.splat != "ellipse")
    throw_usage("--splat must be circle or ellipse, got '" + o.splat + "'");
  n.radius_rule = o.radius == "mean-knn" ? RadiusRule::kMeanKnn : RadiusRule::kCover;
  n.ellipses = o.splat == "ellipse";
  if (n.ellipses && n.radius_rule != RadiusRule::kCover)
    throw_usage("--splat ellipse needs --radius cover (ellipses are fitted to the cover cells)");
  if (n.fit_centres && n.radius_rule != RadiusRule::kCover)
    throw_usage("--fit-centres needs --radius cover");
  return n;
}

nlohmann::json provenance_options(const NormalOptions& o) {
  nlohmann::json j = {{"k", o.k},
                      {"radius_k", o.radius_k},
                      {"radius_scale", o.radius_scale},
                      {"radius", o.radius_rule == RadiusRule::kCover ? "cover" : "mean-knn"},
                      {"splat", o.ellipses ? "ellipse" : "circle"},
                      {"fit_centres", o.fit_centres},
                      {"method", method_name(o.method)},
                      {"orient", orientation_name(o.orient)},
                      {"keep_duplicates", o.keep_duplicates}};
  if (o.viewpoint) j["viewpoint"] = *o.viewpoint;
  return j;
}

}  // namespace

StageSummary run_estimate_normals(const EstimateNormalsOptions& o, const ProgressFn& progress) {
  WriteOptions write;
  write.format = output_format(o.paths.output, o.format);
  const NormalOptions options = normal_options(o);
  Stage stage("estimate-normals", o.paths);
  LoadedCloud doc = stage.read(o.read, progress);
  const NormalReport result = stage.phase(nullptr, "estimating normals", [&] {
    return estimate_normals(doc.cloud, options, progress);
  });
  stage.stamp(doc, provenance_options(options));
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    report = result.to_json();
    const uint64_t rss = peak_rss_bytes();
    report["peak_rss_bytes_per_point"] =
        result.input_points > 0 ? static_cast<double>(rss) / result.input_points : 0.0;
  }
  stage.write(doc, write, std::move(report));
  return {doc.cloud.size(), "points",
          std::to_string(result.duplicates_merged) + " duplicates merged, " +
              std::to_string(result.degenerate_points) + " degenerate"};
}

}  // namespace splatkit::apps
