#include "apps/run_estimate_normals.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "apps/parse_triple.h"
#include "apps/check_tile_halo.h"
#include "apps/tile_walls.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/spill_arena.h"

namespace splatkit::apps {

namespace {

constexpr std::size_t kPieceBytesPerPoint = 200;
// The spill file's peak per point (measured: 85 on a 4M random torus, circles), with a margin;
// ellipses add their axes and minor radii.
constexpr std::size_t kSpillBytesPerPoint = 100, kSpillEllipseBytesPerPoint = 16;
constexpr std::size_t kMinPiecePoints = 1 << 16;

// The output format: --format, else OUT's extension (.ply, .splk), else .splk for '-'.
FileFormat output_format(const std::string& output, const std::string& format) {
  if (format == "ply") return FileFormat::kPly;
  if (format == "splk") return FileFormat::kSplk;
  if (!format.empty()) throw_usage("--format must be ply or splk, got '" + format + "'");
  if (is_stream_path(output)) return FileFormat::kSplk;
  const FileFormat f = output_format_for(output);
  if (f == FileFormat::kPly || lower_extension(output) == "splk") return f;
  throw_usage("OUT must end in .ply or .splk, or be '-' (or give --format ply|splk): " + output);
}

NormalOptions normal_options(const EstimateNormalsOptions& o) {
  NormalOptions n = o.normals;
  if (o.method != "pca" && o.method != "robust")
    throw_usage("--method must be pca or robust, got '" + o.method + "'");
  n.method = o.method == "robust" ? NormalMethod::kRobust : NormalMethod::kPca;
  std::string orient = o.orient.empty() ? "auto" : o.orient;
  if (!o.viewpoint.empty()) {
    if (!o.orient.empty() && o.orient != "viewpoint")
      throw_usage("--viewpoint conflicts with --orient " + o.orient);
    orient = "viewpoint";
    n.viewpoint = parse_triple(o.viewpoint, "--viewpoint");
  }
  n.orient = NormalOrientation::kNone;
  for (NormalOrientation m :
       {NormalOrientation::kAuto, NormalOrientation::kMst, NormalOrientation::kUp,
        NormalOrientation::kViewpoint, NormalOrientation::kSensor, NormalOrientation::kVisibility,
        NormalOrientation::kNone})
    if (orientation_name(m) == orient) n.orient = m;
  if (orientation_name(n.orient) != orient)
    throw_usage("--orient must be auto, mst, up, viewpoint, sensor, visibility or none, got '" +
                orient + "'");
  if (o.normals_from != "auto" && o.normals_from != "estimate" && o.normals_from != "keep")
    throw_usage("--normals must be auto, estimate or keep, got '" + o.normals_from + "'");
  n.input_normals = o.normals_from == "keep"       ? InputNormals::kKeep
                    : o.normals_from == "estimate" ? InputNormals::kEstimate
                                                   : InputNormals::kAuto;
  if (!(n.radius_scale > 0) || !std::isfinite(n.radius_scale))
    throw_usage("--radius-scale must be a positive finite number");
  if (o.radius != "cover" && o.radius != "mean-knn")
    throw_usage("--radius must be cover or mean-knn, got '" + o.radius + "'");
  if (o.splat != "circle" && o.splat != "ellipse")
    throw_usage("--splat must be circle or ellipse, got '" + o.splat + "'");
  n.spatial_order = !o.keep_order;
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
                      {"max_radius_ratio", o.max_radius_ratio},
                      {"radius", o.radius_rule == RadiusRule::kCover ? "cover" : "mean-knn"},
                      {"splat", o.ellipses ? "ellipse" : "circle"},
                      {"fit_centres", o.fit_centres},
                      {"method", method_name(o.method)},
                      {"orient", orientation_name(o.orient)},
                      {"normals", o.input_normals == InputNormals::kKeep       ? "keep"
                                  : o.input_normals == InputNormals::kEstimate ? "estimate"
                                                                               : "auto"},
                      {"keep_duplicates", o.keep_duplicates},
                      {"order", o.spatial_order ? "spatial" : "input"}};
  if (o.viewpoint) j["viewpoint"] = *o.viewpoint;
  return j;
}

// One number of --outliers' parameter list.
template <typename T>
T outlier_number(std::string_view text, const std::string& option) {
  T v{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size())
    throw_usage("--outliers " + option + ": '" + std::string(text) + "' is not a number");
  return v;
}

}  // namespace

namespace {

// One pass of --outliers: sor[:K,SIGMA] or radius[:R,N].
OutlierOptions parse_outlier_pass(const std::string& text, const std::string& whole) {
  const std::size_t colon = text.find(':');
  const std::string rule = text.substr(0, colon);
  OutlierOptions o;
  if (rule == "sor")
    o.rule = OutlierRule::kStatistical;
  else if (rule == "radius")
    o.rule = OutlierRule::kRadius;
  else if (rule == "plane")
    o.rule = OutlierRule::kPlane, o.k = kDefaultPlaneK, o.sigma = kDefaultPlaneT;
  else
    throw_usage(
        "--outliers must be none, sor[:K,SIGMA], radius[:R,N] or plane[:K,T] (passes "
        "joined by +), got '" +
        whole + "'");
  if (colon == std::string::npos) return o;
  const std::string args = text.substr(colon + 1);
  const std::size_t comma = args.find(',');
  if (comma == std::string::npos)
    throw_usage("--outliers " + text + ": give both parameters, e.g. sor:16,2 or radius:0.05,4");
  const std::string_view a(args.data(), comma), b(args.data() + comma + 1, args.size() - comma - 1);
  if (o.rule == OutlierRule::kStatistical) {
    o.k = outlier_number<std::size_t>(a, text);
    o.sigma = outlier_number<double>(b, text);
    if (o.k < 1 || o.k > 1024 || !std::isfinite(o.sigma))
      throw_usage("--outliers " + text + ": K must be 1..1024 and SIGMA finite");
  } else if (o.rule == OutlierRule::kPlane) {
    o.k = outlier_number<std::size_t>(a, text);
    o.sigma = outlier_number<double>(b, text);
    if (o.k < 3 || o.k > 1024 || !(o.sigma > 0) || !std::isfinite(o.sigma))
      throw_usage("--outliers " + text + ": K must be 3..1024 and T positive and finite");
  } else {
    o.radius = outlier_number<double>(a, text);
    o.min_neighbors = outlier_number<std::size_t>(b, text);
    if (!(o.radius > 0) || !std::isfinite(o.radius) || o.min_neighbors > 1024)
      throw_usage("--outliers " + text + ": R must be positive and finite, N at most 1024");
  }
  return o;
}

}  // namespace

std::vector<OutlierOptions> parse_outliers(const std::string& text) {
  std::vector<OutlierOptions> passes;
  if (text.empty() || text == "none") return passes;
  for (std::size_t begin = 0;;) {
    const std::size_t plus = text.find('+', begin);
    const std::string pass = text.substr(begin, plus - begin);
    if (pass == "sor") {
      for (const OutlierOptions& o : default_outlier_passes()) passes.push_back(o);
    } else {
      passes.push_back(parse_outlier_pass(pass, text));
    }
    if (passes.size() > kMaxOutlierPasses)
      throw_usage("--outliers " + text + ": at most " + std::to_string(kMaxOutlierPasses) +
                  " passes");
    if (plus == std::string::npos) break;
    begin = plus + 1;
  }
  return passes;
}

namespace {

// What became of the input's normals, for the summary line.
std::string normals_summary(const NormalReport& r) {
  if (r.normals_source == "estimated")
    return r.input_had_normals > 0
               ? "normals estimated (the input's " + std::to_string(r.input_had_normals) +
                     " replaced; --normals keep keeps them)"
               : "normals estimated";
  const std::string from = r.normals_source.starts_with("faces") ? "from the faces" : "kept";
  return std::to_string(r.given_normals) + " normals " + from + ", " +
         std::to_string(r.output_points - std::min(r.given_normals, r.output_points)) +
         " estimated";
}

}  // namespace

StageSummary run_estimate_normals(const EstimateNormalsOptions& o, const ProgressFn& progress) {
  WriteOptions write;
  write.format = output_format(o.paths.output, o.format);
  NormalOptions options = normal_options(o);
  // With a memory limit the neighbourhood phases run in pieces of a quarter of it (a piece with
  // its halo, kd-tree and per-point values takes about kPieceBytesPerPoint per point); method
  // robust and --fit-centres run over the whole cloud, its arrays paged from the spill file.
  if (o.memory.max_bytes > 0 && options.method == NormalMethod::kPca && !options.fit_centres)
    options.piece_points =
        std::max<std::size_t>(kMinPiecePoints, o.memory.max_bytes / 4 / kPieceBytesPerPoint);
  const std::vector<OutlierOptions> outliers = parse_outliers(o.outliers);
  if (!o.outliers_out.empty()) {
    if (outliers.empty()) throw_usage("--outliers-out needs --outliers sor or radius");
    if (format_of_extension(o.outliers_out) == FileFormat::kUnknown &&
        !is_stream_path(o.outliers_out))
      throw_usage(
          "--outliers-out's extension names no format (.ply, .splk, .xyz, .off, .las, "
          ".laz): " +
          o.outliers_out);
    writable_format(o.outliers_out, {});
  }
  Stage stage("estimate-normals", o.paths);
  stage.check_side_output("--outliers-out", o.outliers_out);
  LoadedCloud doc = stage.read(o.read, progress);
  // As for a single point: no splat can be made (and an empty file with no normals would only
  // fail the next tool, with a message about normals).
  if (doc.cloud.size() == 0) throw_bad_input(stage.input_name(), "the file has no points");
  spill::check_room(doc.cloud.size() *
                    (kSpillBytesPerPoint + (options.ellipses ? kSpillEllipseBytesPerPoint : 0)));
  // Outliers go first, on the cloud as read (duplicates included), as PCL's filters see it.
  const std::size_t points_read = doc.cloud.size();
  OutlierPassesResult removed;
  std::unique_ptr<OutputFile> aside_file;
  if (!outliers.empty()) {
    removed = stage.phase(nullptr, "removing outliers",
                          [&] { return find_outliers(doc.cloud.positions, outliers); });
    LoadedCloud aside;
    aside.cloud = split_cloud(doc.cloud, removed.outlier);
    aside.format = doc.format;
    if (!o.outliers_out.empty()) {  // committed with OUT
      aside_file = std::make_unique<OutputFile>(o.outliers_out);
      write_cloud(aside, *aside_file);
    }
    if (doc.cloud.size() == 0)
      throw_bad_input(stage.input_name(), "--outliers " + o.outliers +
                                              " removed every one of its " +
                                              std::to_string(points_read) + " points");
  }
  // A tile of splat-tile: its views do not look through the borders where the survey goes on.
  options.walls = tile_walls(doc.metadata, doc.cloud);
  const TileHaloCheck halo = stage.phase("check_tile_halo", "checking the tile's halo",
                                         [&] { return check_tile_halo(doc.metadata, doc.cloud); });
  if (halo.short_of > 0)
    std::fprintf(stderr,
                 "estimate-normals: warning: %s: the tile's halo (%.6g) does not hold the "
                 "neighbourhoods of %zu of its points near a cut (they reach %.6g beyond the "
                 "tile): their normals and radii may differ from a run over the whole survey; "
                 "cut the survey again with splat-tile --halo %.6g or more\n",
                 stage.input_name().c_str(), halo.halo, halo.short_of, halo.needed, halo.needed);
  const NormalReport result = stage.phase(nullptr, "estimating normals", [&] {
    return estimate_normals(doc.cloud, options, progress);
  });
  nlohmann::json stamp = provenance_options(options);
  if (!outliers.empty()) stamp["outliers"] = o.outliers;
  stage.stamp(doc, stamp);
  nlohmann::json report;
  if (!o.paths.report.empty()) {
    report = result.to_json();
    if (!outliers.empty()) report["outliers"] = removed.to_json(outliers);
    report["input_points"] = points_read;  // before the outliers went
    report["tile_halo"] = halo.to_json();
    const uint64_t rss = peak_rss_bytes();
    report["peak_rss_bytes_per_point"] =
        static_cast<double>(rss) / static_cast<double>(points_read);
  }
  OutputFile* also[] = {aside_file.get()};
  stage.write(doc, write, std::move(report), also);
  return {doc.cloud.size(), "points",
          (!outliers.empty() ? std::to_string(removed.removed) + " outliers removed, "
                             : std::string()) +
              std::to_string(result.duplicates_merged) + " duplicates merged, " +
              std::to_string(result.degenerate_points) + " degenerate, " + normals_summary(result) +
              ", oriented by " + result.orientation.value("method", std::string("none"))};
}

}  // namespace splatkit::apps
