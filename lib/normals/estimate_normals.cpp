#include "normals/estimate_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "normals/bound_radii.h"
#include "normals/cover_splat.h"
#include "normals/fill_isolated_radii.h"
#include "normals/fit_splat_centres.h"
#include "normals/merge_duplicates.h"
#include "normals/orient_normals_mst.h"
#include "normals/orient_normals_viewpoint.h"
#include "normals/pca_normals_and_radii.h"
#include "normals/refit_splats.h"
#include "normals/resolve_degenerate_normals.h"
#include "normals/robust_normals.h"
#include "normals/select_face_normals.h"
#include "normals/splat_pieces.h"
#include "normals/visibility_votes.h"
#include "normals/widen_flat_normals.h"
#include "splatkit/error.h"
#include "splatkit/gathered.h"
#include "splatkit/morton_order.h"
#include "splatkit/seconds_since.h"
#include "splatkit/shrinkable_array.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vertex_normals.h"

namespace splatkit {

namespace {

void check_options(const NormalOptions& o) {
  if (o.k < 3) throw_usage("-k must be at least 3 (a plane needs 3 points)");
  if (o.radius_k < 1) throw_usage("--radius-k must be at least 1");
  if (o.max_radius_ratio != 0 && !(o.max_radius_ratio >= 1 && std::isfinite(o.max_radius_ratio)))
    throw_usage("--max-radius-ratio must be 0 (no bound) or a finite number >= 1");
  if (!std::isfinite(o.radius_scale) || !(o.radius_scale > 0))
    throw_usage("--radius-scale must be a finite number > 0");
  if (o.ellipses && o.radius_rule != RadiusRule::kCover)
    throw_usage("--splat ellipse needs --radius cover (ellipses are fitted to the cover cells)");
  if (o.fit_centres && o.radius_rule != RadiusRule::kCover)
    throw_usage("--fit-centres needs --radius cover");
}

nlohmann::json robust_stats_json(const RobustNormalStats& r) {
  return {{"candidates", r.candidates},
          {"refined", r.refined},
          {"threshold", r.threshold},
          {"median_variation", r.median_variation},
          {"k", r.k},
          {"noisy", r.noisy}};
}

constexpr float kRefitCos = 0.98480775f;  // cos 10°

bool uses_graph(NormalOrientation o) {
  return o == NormalOrientation::kMst || o == NormalOrientation::kVisibility;
}

// Each point's sensor position in the positions' frame (points in the order `order` gives).
std::vector<std::array<double, 3>> sensor_positions(const SplatCloud& cloud,
                                                    const std::vector<uint32_t>& order) {
  const std::array<std::string, 3> names = sensor_attributes(cloud);
  std::vector<std::array<double, 3>> out(order.size());
  for (std::size_t a = 0; a < 3; ++a) {
    const ExtraValues& values = cloud.find_extra(names[a])->values;
    for (std::size_t t = 0; t < order.size(); ++t) out[t][a] = values[order[t]] - cloud.origin[a];
  }
  return out;
}

// Phase 7. The graph methods join the kNN rows found before the radius bound (they take them);
// `given` (#N or empty) marks the normals taken from the input, which vote for their own signs;
// `layered` (#N or empty) the points whose k-row showed no plane (widen_flat_normals.h).
void orient(SplatCloud& cloud, std::optional<ShrinkableArray>& rows, const NormalOptions& o,
            NormalOrientation method, const std::vector<uint32_t>& order,
            const std::vector<uint8_t>& given, const std::vector<uint8_t>& layered,
            std::vector<float>& face_cuts, NormalReport& report) {
  nlohmann::json& j = report.orientation;
  if (uses_graph(method)) {
    std::vector<float> votes;
    if (method == NormalOrientation::kVisibility) {
      VisibilityOptions vo;
      vo.up = o.up;
      vo.walls = o.walls;
      VisibilityStats vs;
      votes = visibility_votes(cloud.positions, cloud.normals, cloud.radii, vo, &vs);
      j["seen"] = vs.seen;
      if (!o.walls.empty()) j["walls"] = o.walls.size();
    }
    if (!given.empty()) {
      votes.resize(cloud.size(), 0.0f);
      for (std::size_t i = 0; i < given.size(); ++i)
        if (given[i]) votes[i] = 1;
    }
    OrientRegionsOptions regions;
    regions.split_gaps = method == NormalOrientation::kVisibility || !given.empty();
    regions.evidence = votes;
    regions.layered = layered;
    regions.blended_layers = o.method == NormalMethod::kPca;
    for (std::size_t i = 0; i < given.size() && !face_cuts.empty(); ++i)
      if (given[i]) face_cuts[i] = std::numeric_limits<float>::quiet_NaN();  // not the faces'
    regions.face_cuts = face_cuts;
    const OrientStats stats =
        orient_normals_mst(std::move(*rows), cloud.positions, cloud.normals, kOrientK, regions);
    rows.reset();
    report.flipped_points = stats.flipped;
    report.components = stats.components;
    j["sheets"] = stats.sheets;
    j["relabelled"] = stats.relabelled;
    j["settled"] = stats.settled;
    if (!votes.empty()) {
      j["by_evidence"] = stats.by_evidence;
      j["against_evidence"] = stats.against_evidence;
    }
  } else if (method == NormalOrientation::kViewpoint) {
    const std::array<double, 3>& v = o.viewpoint ? *o.viewpoint : *cloud.viewpoint;
    const std::array<double, 3> local = {v[0] - cloud.origin[0], v[1] - cloud.origin[1],
                                         v[2] - cloud.origin[2]};
    report.flipped_points = orient_normals_viewpoint(cloud.positions, cloud.normals, local);
  } else if (method == NormalOrientation::kSensor) {
    report.flipped_points =
        orient_normals_sensors(cloud.positions, cloud.normals, sensor_positions(cloud, order));
  } else if (method == NormalOrientation::kUp) {
    report.flipped_points = orient_normals_up(cloud.normals, o.up);
  }
  j["flipped"] = report.flipped_points;
}

// A valid given normal: finite, of length within 10 % of 1 (normalised, unless it is unit to
// within float rounding: kept as it is); else zero.
Vec3f valid_normal(const Vec3f& n) {
  const float l2 = squared_norm(n);
  if (!std::isfinite(l2) || !(l2 > 0.81f && l2 < 1.21f)) return {0, 0, 0};
  return std::fabs(l2 - 1) <= 1e-5f ? n : n * (1.0f / std::sqrt(l2));
}

// The normals the cloud brings (input order, after merging): its own valid ones with kKeep, its
// faces' area-weighted ones for a mesh (kAuto and kKeep, where it has none of its own); empty
// when none apply. Zero where a point has none.
std::vector<Vec3f> given_normals(const SplatCloud& cloud, const NormalOptions& o,
                                 NormalReport& report) {
  std::vector<Vec3f> given(cloud.size(), Vec3f{0, 0, 0});
  std::size_t own = 0;
  if (cloud.has_normals())
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      given[i] = valid_normal(cloud.normals[i]);
      own += squared_norm(given[i]) > 0;
    }
  report.input_had_normals = own;
  if (o.input_normals == InputNormals::kEstimate) return {};
  const bool keep = o.input_normals == InputNormals::kKeep && own > 0;
  if (!keep) std::fill(given.begin(), given.end(), Vec3f{0, 0, 0});
  std::size_t from_faces = 0;
  if (cloud.face_count() > 0) {
    const std::vector<Vec3f> faces = vertex_normals(cloud);
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (!(squared_norm(given[i]) > 0) && squared_norm(faces[i]) > 0) {
        given[i] = normalized(faces[i]);
        ++from_faces;
      }
  }
  if (!keep && from_faces == 0) return {};
  report.given_normals = (keep ? own : 0) + from_faces;
  report.normals_source = keep ? "input" : "faces";
  if (report.given_normals < cloud.size()) report.normals_source += "+estimated";
  return given;
}

}  // namespace

std::string method_name(NormalMethod m) { return m == NormalMethod::kPca ? "pca" : "robust"; }

std::string orientation_name(NormalOrientation o) {
  switch (o) {
    case NormalOrientation::kAuto:
      return "auto";
    case NormalOrientation::kMst:
      return "mst";
    case NormalOrientation::kUp:
      return "up";
    case NormalOrientation::kViewpoint:
      return "viewpoint";
    case NormalOrientation::kSensor:
      return "sensor";
    case NormalOrientation::kVisibility:
      return "visibility";
    default:
      return "none";
  }
}

std::array<std::string, 3> sensor_attributes(const SplatCloud& cloud) {
  for (const char* prefix : {"sensor_", "scanner_", "vp_"}) {
    const std::string p = prefix;
    if (cloud.find_extra(p + "x") && cloud.find_extra(p + "y") && cloud.find_extra(p + "z"))
      return {p + "x", p + "y", p + "z"};
  }
  return {};
}

std::pair<NormalOrientation, std::string> choose_orientation(const SplatCloud& cloud,
                                                             const NormalOptions& options) {
  if (options.orient != NormalOrientation::kAuto) return {options.orient, "given"};
  if (const auto s = sensor_attributes(cloud); !s[0].empty())
    return {NormalOrientation::kSensor,
            "the input has per-point sensor positions (" + s[0] + ", " + s[1] + ", " + s[2] + ")"};
  if (options.viewpoint) return {NormalOrientation::kViewpoint, "--viewpoint given"};
  if (cloud.viewpoint)
    return {NormalOrientation::kViewpoint, "the input records its scanner position"};
  return {NormalOrientation::kVisibility,
          "no scanner position in the input: visibility from above and around, propagated "
          "within smooth regions"};
}

nlohmann::json NormalReport::to_json() const {
  const double total = timings.value("total", 0.0);
  return {{"input_points", input_points},
          {"output_points", output_points},
          {"duplicates_merged", duplicates_merged},
          {"degenerate_points", degenerate_points},
          {"unresolved_points", unresolved_points},
          {"isolated_points", isolated_points},
          {"bounded_radii", bounded_radii},
          {"radii_over_bound", radii_over_bound},
          {"widened_points", widened_points},
          {"face_selected_points", face_selected},
          {"face_noise", face_noise},
          {"two_face_points", two_face_points},
          {"refitted_points", refitted_points},
          {"mean_centre_shift", mean_centre_shift},
          {"flipped_points", flipped_points},
          {"components", components},
          {"orientation", orientation},
          {"normals_source", normals_source},
          {"given_normals", given_normals},
          {"input_had_normals", input_had_normals},
          {"robust", robust},
          {"pieces", pieces},
          {"timings_s", timings},
          {"points_per_s", total > 0 ? static_cast<double>(output_points) / total : 0.0}};
}

namespace {

// The inverse of gathered, in place: v becomes w with w[order[t]] = v[t] (empty stays empty).
template <class T>
void scatter(std::vector<T>& v, const std::vector<uint32_t>& order) {
  if (v.empty()) return;
  std::vector<T> out(v.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1 << 14), [&](const auto& r) {
    for (std::size_t t = r.begin(); t < r.end(); ++t) out[order[t]] = v[t];
  });
  v = std::move(out);
}

// The extra attribute's values gathered as `gathered` does.
void gather_extra(ExtraValues& values, const std::vector<uint32_t>& order) {
  if (values.empty()) return;
  visit_scalar_type(values.type(), [&](auto zero) {
    using T = decltype(zero);
    const std::span<T> v = values.as<T>();
    const std::vector<T> out = gathered(v, order);
    std::copy(out.begin(), out.end(), v.begin());
  });
}

// Phase 3 to the refits over the whole cloud (index: over its positions, in Morton order).
template <class Timed>
void whole_cloud_splats(const SpatialIndex& index, SplatCloud& cloud, const NormalOptions& options,
                        const std::vector<uint32_t>& order, NormalReport& report, Timed& timed,
                        const ProgressFn& progress, std::vector<Bridge>& bridges,
                        std::vector<uint8_t>& widened, std::span<uint32_t> bound_rows,
                        std::vector<float>& face_cuts) {
  const std::size_t n = cloud.size();
  const bool robust = options.method == NormalMethod::kRobust;
  const bool cover = options.radius_rule == RadiusRule::kCover;
  std::vector<uint8_t> flags(n, 0);  // kDegenerate, kOpenCell
  // Cover rule: points whose normal changed after phase 3 or whose cell stayed open.
  std::vector<uint32_t> refit;
  std::vector<float> variation(robust ? n : 0);
  std::vector<float> ratio(n);  // the PCA's λ0 / λ1 (widen_flat_normals.h)
  std::vector<FaceModel> models(robust ? 0 : n);  // select_face_normals.h
  timed("normals_radii", [&] {
    pca_normals_and_radii(index, cloud, options, flags, variation, {}, progress, bound_rows, ratio,
                          models);
  });

  progress(0.6, "degenerate");
  timed("degenerate", [&] {
    std::vector<uint32_t> points;
    for (std::size_t i = 0; i < n; ++i) {
      if (flags[i] & kDegenerateFlag) points.push_back(static_cast<uint32_t>(i));
      if (flags[i] & kOpenCellFlag) refit.push_back(static_cast<uint32_t>(i));
    }
    std::vector<uint32_t> to(points.size());
    const DegenerateStats stats =
        resolve_degenerate_normals(index, cloud.positions, points, options.k, options.radius_k,
                                   cloud.normals, cloud.radii, nullptr, {}, to);
    for (std::size_t p = 0; p < points.size(); ++p)
      if (to[p] != kNoBridge) bridges.push_back({points[p], to[p]});
    report.degenerate_points = points.size();
    report.unresolved_points = stats.unresolved;
    if (cover) refit.insert(refit.end(), points.begin(), points.end());
  });
  if (!robust) {
    progress(0.62, "widen");
    timed("widen", [&] {
      std::vector<uint32_t> points;
      for (std::size_t i = 0; i < n; ++i)
        if (!(flags[i] & kDegenerateFlag) && ratio[i] > kWidenRatio)
          points.push_back(static_cast<uint32_t>(i));
      report.widened_points =
          widen_flat_normals(index, cloud.positions, points, options.k, cloud.normals, {}, models);
      for (uint32_t i : points) widened[i] = 1;
      if (cover) refit.insert(refit.end(), points.begin(), points.end());
      if (points.empty()) return;
      for (uint32_t i : points) report.two_face_points += models[i].a != models[i].b;
      if (!thin_parts(report.two_face_points, points.size())) return;
      const float noise = face_noise(models, points);
      std::vector<uint32_t> blended;
      for (std::size_t i = 0; i < n; ++i)
        if (!(flags[i] & kDegenerateFlag) && ratio[i] > kSelectRatio)
          blended.push_back(static_cast<uint32_t>(i));
      std::vector<Vec3f> chosen(cloud.normals);
      face_cuts.assign(n, std::numeric_limits<float>::quiet_NaN());
      report.face_selected = select_face_normals(index, cloud.positions, blended, options.k,
                                                 cloud.normals, models, noise, chosen, {},
                                                 face_cuts);
      report.face_noise = noise;
      for (uint32_t i : blended)
        if (cover && !(chosen[i] == cloud.normals[i])) refit.push_back(i);
      cloud.normals.swap(chosen);
    });
  } else {
    // The robust fit keeps its normals, but the orientation reads the same rows as layered, where
    // a sheet edge must be confirmed: the two sides of a thin wall or slab (measured, noisy
    // scan-line city: walls facing out 61 -> 98 %).
    for (std::size_t i = 0; i < n; ++i)
      if (!(flags[i] & kDegenerateFlag) && ratio[i] > kWidenRatio) widened[i] = 1;
  }
  std::vector<float>().swap(ratio);
  std::vector<uint8_t>().swap(flags);  // (`= {}` would keep the capacity)

  if (robust) {
    progress(0.65, "robust");
    std::vector<Vec3f> before;
    if (cover) before = cloud.normals;
    timed("robust", [&] {
      RobustNormalOptions ro;
      ro.pca_k = options.k;
      ro.stream_ids = order;  // the same random samples as over the input's numbering
      report.robust =
          robust_stats_json(robust_normals(index, cloud.positions, variation, cloud.normals, ro));
    });
    std::vector<float>().swap(variation);
    for (std::size_t i = 0; i < before.size(); ++i)
      if (!(before[i] == cloud.normals[i])) refit.push_back(static_cast<uint32_t>(i));
  }
  if (!refit.empty()) {
    progress(0.8, "splats");
    std::sort(refit.begin(), refit.end());
    refit.erase(std::unique(refit.begin(), refit.end()), refit.end());
    timed("refit_splats",
          [&] { refit_splats(index, cloud, options, refit, kWideRowFactor * row_size(options)); });
    report.refitted_points = refit.size();
  }
}

}  // namespace

NormalReport estimate_normals(SplatCloud& cloud, const NormalOptions& options,
                              const ProgressFn& progress) {
  check_options(options);
  if (options.piece_points > 0 && (options.method != NormalMethod::kPca || options.fit_centres))
    throw_usage("processing in pieces needs --method pca and no --fit-centres");
  if (options.orient == NormalOrientation::kViewpoint && !options.viewpoint && !cloud.viewpoint)
    throw_usage(
        "--orient viewpoint needs --viewpoint x,y,z (the input carries no scanner position)");
  if (options.orient == NormalOrientation::kSensor && sensor_attributes(cloud)[0].empty())
    throw_usage(
        "--orient sensor needs per-point sensor positions (attributes sensor_x, sensor_y, "
        "sensor_z, or scanner_*, vp_*); the input has none");
  if (!(std::fabs(squared_norm(options.up) - 1) < 1e-3f))
    throw_usage("the up direction must be a unit vector");
  // Named by its input number, before merging and renumbering.
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!std::isfinite(cloud.positions[i].x) || !std::isfinite(cloud.positions[i].y) ||
        !std::isfinite(cloud.positions[i].z))
      throw Error(ErrorKind::kBadInput,
                  "point " + std::to_string(i) + " has a non-finite coordinate");
  NormalReport report;
  report.input_points = cloud.size();
  const std::pair<NormalOrientation, std::string> chosen = choose_orientation(cloud, options);
  const NormalOrientation method = chosen.first;  // (a lambda below captures it: no binding)
  report.orientation = {{"method", orientation_name(method)}, {"reason", chosen.second}};
  const Clock::time_point start = Clock::now();
  auto timed = [&](const char* phase, auto&& work) {
    const Clock::time_point t0 = Clock::now();
    work();
    report.timings[phase] = seconds_since(t0);
  };

  // Every stage below runs over the points renumbered in Morton order (morton_order.h: a
  // spatial order, so a point's neighbours are mostly near it in memory whatever the input's
  // order, and one that a subset of the cloud reproduces), and the results are put back in the
  // input's order at the end unless spatial_order. Ties between equally distant neighbours are
  // broken by the new numbers. Duplicates are merged first; without faces (which are remapped in
  // the input's numbering) and pieces (where nothing may read the cloud at random, and the merge
  // below reads a map through the order), they are found in the sorted keys, where they lie side
  // by side, and leave the order afterwards: the same order and points (1M torus, 2 threads: the
  // hashing merge took 0.04-0.07 s).
  std::vector<uint32_t> order;
  const bool merge_sorted =
      !options.keep_duplicates && cloud.face_count() == 0 && options.piece_points == 0;
  if (!options.keep_duplicates) progress(0.0, "duplicates");
  if (merge_sorted) {
    std::vector<DuplicatePoint> copies;
    timed("order", [&] { order = morton_sort(cloud.positions, copies); });
    timed("merge_duplicates",
          [&] { report.duplicates_merged = merge_sorted_duplicates(cloud, order, copies); });
  } else if (!options.keep_duplicates) {
    timed("merge_duplicates", [&] { report.duplicates_merged = merge_duplicates(cloud).merged; });
  }
  const std::size_t n = cloud.size();
  report.output_points = n;
  // (It reads the positions only for faces, which leave them in the input's order.)
  std::vector<Vec3f> given = given_normals(cloud, options, report);
  progress(0.05, "kd-tree");
  if (!merge_sorted) timed("order", [&] { order = morton_sort(cloud.positions); });
  if (!given.empty()) given = gathered(given, order);
  cloud.normals.assign(n, Vec3f{0, 0, 1});
  cloud.radii.assign(n, 0.0f);
  cloud.axes.assign(options.ellipses ? n : 0, Vec3f{1, 0, 0});
  cloud.minor_radii.assign(options.ellipses ? n : 0, 0.0f);
  SpatialIndex index;
  std::optional<SplatPieces> pieces;
  // The MST orientation's kNN rows (the radius bound reads its neighbours from them too), and
  // the edges from thread points to the next scan line that take the last place of their rows.
  std::optional<ShrinkableArray> rows;
  std::vector<Bridge> bridges;
  // The points whose k-row showed no plane: PCA widens their rows, both methods' orientation
  // keeps the two layers of such a row apart (orient_normals_mst.h, OrientRegionsOptions::layered).
  std::vector<uint8_t> widened(n);
  // Where a point took two faces' normal, the cut between them (select_face_normals.h), which
  // keeps the orientation's sheet edges off the other face (empty when no point was widened).
  std::vector<float> face_cuts;
  const bool mst = uses_graph(method) && n > 0;
  // Without rows: each point's kBoundRadiiK nearest other points, for the radius bound (below).
  std::unique_ptr<uint32_t[]> bound_rows;
  if (options.piece_points > 0 && n > options.piece_points) {
    pieces.emplace(cloud.positions, options.piece_points);
    // In pieces they are the heads of the normals' own rows, when those are longer (without
    // pieces that would hold them through the normals' peak; a pass of their own is cheap there,
    // and a second load of every piece is not).
    const std::size_t head = kOrientK - 1;
    if (mst && row_size(options) > head && n >= row_size(options)) rows.emplace(n * head);
    timed("normals_radii", [&] {
      pieces->normals_and_splats(
          cloud, options, report, progress,
          rows ? std::span<uint32_t>(rows->data(), rows->size()) : std::span<uint32_t>(), bridges,
          widened, face_cuts);
    });
  } else {
    // Without the orientation's rows, the radius bound reads its neighbours from the heads of the
    // normals' own rows (the 8 nearest of a 16-row are what an 8 + 1 query gives), kept from the
    // normals pass, instead of a kNN pass of its own per pass: 32 bytes per point, held until the
    // bound (1M torus, --orient none, 2 threads: the bound 0.19 -> 0.03 s).
    if (!mst && options.max_radius_ratio > 0 && row_size(options) > kBoundRadiiK &&
        n > row_size(options))
      bound_rows.reset(new uint32_t[n * kBoundRadiiK]);  // (uninitialised: every row is written)
    timed("index", [&] { index = SpatialIndex(cloud.positions); });
    whole_cloud_splats(
        index, cloud, options, order, report, timed, progress, bridges, widened,
        std::span<uint32_t>(bound_rows.get(), bound_rows ? n * kBoundRadiiK : std::size_t{0}),
        face_cuts);
  }
  // The given normals replace the estimated ones; the splats of those that turn by more than
  // 10° are fitted again in their plane (not in pieces: the index is gone there).
  std::vector<uint8_t> is_given;
  if (!given.empty()) {
    is_given.assign(n, 0);
    std::vector<uint32_t> refit;
    for (std::size_t i = 0; i < n; ++i) {
      if (!(squared_norm(given[i]) > 0)) continue;
      is_given[i] = 1;
      if (std::fabs(dot(given[i], cloud.normals[i])) < kRefitCos) refit.push_back(uint32_t(i));
      cloud.normals[i] = given[i];
    }
    if (!pieces && !refit.empty())
      timed("refit_given", [&] {
        refit_splats(index, cloud, options, refit, kWideRowFactor * row_size(options));
      });
  }
  if (n > 0) report.isolated_points = fill_isolated_radii(cloud.radii);
  if (options.ellipses)  // isolated points: circles of the radius they were given
    for (std::size_t i = 0; i < n; ++i)
      if (cloud.minor_radii[i] == 0) {
        cloud.minor_radii[i] = cloud.radii[i];
        cloud.axes[i] = tangent_axis(cloud.normals[i]);
      }

  // Otherwise they are found here: the radius bound reads its neighbours from them instead of a
  // kNN pass of its own per pass (the nearest of a longer row are the same points), and without
  // centre fitting the index goes before the bound and the orientation's peaks.
  if (mst && !rows)
    timed("knn_rows", [&] {
      rows = orient_knn_rows(
          [&](std::size_t k, std::span<uint32_t> out) {
            if (pieces)
              pieces->knn_rows(k, out);
            else
              index_knn_rows(index, k, out);
          },
          n, kOrientK);
    });
  if (const std::size_t w = std::min(kOrientK, n) - 1; rows && w > kBoundRadiiK) {
    // A thread point's k nearest lie on its own scan line: without an edge off it, each line (or
    // a few) would be a component of the graph, oriented on its own. The radius bound reads the
    // first kBoundRadiiK entries of a row: the last one is free.
    for (const Bridge& b : bridges) (*rows)[std::size_t{b.from} * w + w - 1] = b.to;
  }
  bridges = {};
  if (options.max_radius_ratio > 0 && n > 1) {
    progress(0.81, "bound radii");
    timed("bound_radii", [&] {
      std::function<std::vector<float>(const std::vector<float>&)> medians;
      if (rows)
        medians = [&](const std::vector<float>& r) {
          return row_median_radii(std::span<const uint32_t>(rows->data(), rows->size()),
                                  std::min(kOrientK, n) - 1, r, kBoundRadiiK);
        };
      else if (bound_rows)
        medians = [&](const std::vector<float>& r) {
          return row_median_radii(std::span<const uint32_t>(bound_rows.get(), n * kBoundRadiiK),
                                  kBoundRadiiK, r, kBoundRadiiK);
        };
      else if (pieces)
        medians = [&](const std::vector<float>& r) {
          return pieces->neighbour_median_radii(r, kBoundRadiiK);
        };
      else
        medians = [&](const std::vector<float>& r) {
          return neighbour_median_radii(index, r, kBoundRadiiK);
        };
      const BoundRadiiResult b =
          bound_radii(medians, cloud.radii, cloud.minor_radii, options.max_radius_ratio);
      // A sparse cluster (vegetation, a patch far from the rest) whose 8 nearest are as large
      // as itself passes that bound; over its 32 nearest, the denser surface around it counts.
      const BoundRadiiResult wide =
          pieces ? bound_radii(
                       [&](const std::vector<float>& r) {
                         return pieces->neighbour_median_radii(r, kWideBoundK);
                       },
                       cloud.radii, cloud.minor_radii, kWideBoundRatio, kWideBoundPasses)
                 : bound_wide_radii(index, cloud.positions, cloud.radii, cloud.minor_radii,
                                    kWideBoundRatio, kWideBoundK, kWideBoundPasses);
      report.bounded_radii = b.capped + wide.capped;
      report.radii_over_bound = b.over + wide.over;
    });
  }
  bound_rows.reset();
  if (!options.fit_centres) index = SpatialIndex();
  if (options.fit_centres && n > 0) {
    progress(0.82, "centres");
    timed("fit_centres", [&] {
      report.mean_centre_shift =
          fit_splat_centres(index, cloud.positions, cloud.normals, row_size(options));
    });
  }
  index = SpatialIndex();
  if (method != NormalOrientation::kNone && n > 0) {
    progress(0.85, "orientation");
    timed("orient",
          [&] {
            orient(cloud, rows, options, method, order, is_given, widened, face_cuts, report);
          });
    for (std::size_t i = 0; i < is_given.size(); ++i)  // kept as given, whatever their set says
      if (is_given[i]) cloud.normals[i] = given[i];
  }
  if (pieces)
    report.pieces = {{"pieces", pieces->stats().pieces},
                     {"halo_points", pieces->stats().halo_points},
                     {"reruns", pieces->stats().reruns}};
  timed("reorder", [&] {
    if (options.spatial_order) {  // the rest follows the splats into the tree's order
      if (!cloud.colors.empty()) cloud.colors = gathered(cloud.colors, order);
      for (ExtraAttribute& extra : cloud.extras) gather_extra(extra.values, order);
      if (!cloud.face_indices.empty()) {
        std::vector<uint32_t> place(n);
        for (std::size_t t = 0; t < n; ++t) place[order[t]] = static_cast<uint32_t>(t);
        for (uint32_t& v : cloud.face_indices) v = place[v];
      }
      return;
    }
    for (auto* v : {&cloud.positions, &cloud.normals, &cloud.axes}) scatter(*v, order);
    for (auto* v : {&cloud.radii, &cloud.minor_radii}) scatter(*v, order);
  });
  if (options.radius_scale != 1.0f) {
    for (float& r : cloud.radii) r *= options.radius_scale;
    for (float& r : cloud.minor_radii) r *= options.radius_scale;
  }
  report.timings["total"] = seconds_since(start);
  progress(1.0, "done");
  return report;
}

}  // namespace splatkit
