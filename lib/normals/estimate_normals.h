// estimate_normals: turns a raw point cloud into splats — unit normal and disc radius per point —
// the work behind the estimate-normals tool. PCA normals and MST orientation after [Hoppe92],
// crease-preserving normals after [Li10], radii by the rule of [IvoMSc] ch. 6
// (docs/references.md).
//
// Pipeline, each phase timed in the report:
//   1. merge exact duplicates (merge_duplicates.h) unless keep_duplicates: fewer points out, the
//      first occurrence's attributes kept (without faces or pieces, found in phase 2's sorted
//      keys: merge_sorted_duplicates);
//   2. renumber the points in Morton order (morton_order.h; kNN ties are broken by these numbers)
//      and build the kd-tree (SpatialIndex) over them, or, with piece_points, split them into
//      pieces that phases 3 to 5 and the orientation's kNN rows run on (splat_pieces.h);
//   3. one streamed kNN pass with max(k, radius_k + 1) points per row (the point itself first):
//      PCA normal over the first k entries (neighborhood_pca.h), splat radius from the first
//      radius_k neighbours (splat_radius.h) or, by default, the splat that covers the point's
//      tangent-plane cell among the whole row (cover_splat.h); no n×k array is ever held;
//   4. degenerate neighbourhoods (fewer than 3 distinct points, collinear, or a thread of points
//      along one scan line, straight or curved: is_thread in neighborhood_pca.h) get their normal
//      from a wider neighbourhood and an edge to the next scan line for the orientation's graph
//      (resolve_degenerate_normals.h); isolated points (no neighbour at a
//      finite, positive distance) get the median radius (fill_isolated_radii.h), never 0;
//   5. method robust: crease-preserving refinement (robust_normals.h); method pca: the points
//      whose row shows no plane take the normal of a row twice as long (widen_flat_normals.h:
//      two parallel faces' where it holds both faces of a thin wall), then the points whose row
//      blends take the face model among their neighbours' that passes through them and holds
//      most of their 2k-row (select_face_normals.h; 12 bytes per point while it runs);
//      with the cover rule, the splats of the points whose normal phases 4 and 5 changed are
//      fitted again in their new tangent plane (one kNN query each);
//   6. with orient mst or visibility, each point's kOrientK - 1 nearest other points
//      ("knn_rows": one kNN pass, or in pieces the heads of phase 3's rows), the last one
//      replaced by phase 4's edge to the next scan line for a thread point; the radius bound
//      (bound_radii.h, max_radius_ratio) reads its neighbours from them when they exist, else
//      from the heads of phase 3's rows kept for it (whole cloud, k > 8) or kNN passes of its
//      own, then the wider bound (3 × the median of the 32 nearest,
//      bound_wide_radii); normals given by the input (InputNormals) replace the estimated ones
//      before it, their splats fitted again where they turn by more than 10°;
//   7. orientation (choose_orientation resolves kAuto): visibility (orient_normals_mst.h's
//      regional variant over those rows, signed by visibility_votes.h), mst (consistent over
//      those rows, outward per component), up, viewpoint or sensor (orient_normals_viewpoint.h),
//      or none (canonical sign, see neighborhood_pca.h); given normals vote for their own signs
//      and come out as they went in.
//
// Output: the same cloud (positions, colours, extras, faces carried through; faces remapped after
// merging), in the input's order or with spatial_order in Morton order (morton_order.h), with
// normals and radii replaced; never NaN. Deterministic: byte-identical results for any thread count
// (every per-point result depends only on the point's own kNN row, and kNN rows are exact with ties
// broken by index), and the same with or without pieces. Runs in parallel with TBB under the
// caller's limits.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "normals/visibility_votes.h"
#include "splatkit/progress.h"
#include "splatkit/splat_cloud.h"

namespace splatkit {

enum class NormalMethod { kPca, kRobust };
// kAuto: kSensor when the input has per-point sensor positions, else kViewpoint when a scanner
// position is given or recorded in the input, else kVisibility (choose_orientation).
enum class NormalOrientation { kAuto, kMst, kUp, kViewpoint, kSensor, kVisibility, kNone };
// Where the normals come from. kAuto: a mesh's (a cloud with faces) from its faces, else
// estimated; kKeep: the input's valid normals are kept (a mesh's face normals where the input
// has none), estimated only where missing or invalid; kEstimate: always estimated.
enum class InputNormals { kAuto, kEstimate, kKeep };
// kCover: each splat reaches the farthest vertex of its tangent-plane Voronoi cell among its row's
// neighbours (cover_splat.h), capped at kCoverCapScale times the mean-kNN radius: no holes on
// irregular sampling. kMeanKnn: the mean distance to the radius_k nearest neighbours ([IvoMSc]
// ch. 6; leaves about 2.5 % of an i.i.d. random sample's surface uncovered).
enum class RadiusRule { kCover, kMeanKnn };

inline constexpr float kCoverCapScale = 2.0f;
inline constexpr float kDefaultMaxRadiusRatio = 5.0f;

struct NormalOptions {
  std::size_t k = 16;         // points per PCA neighbourhood, the point itself included (>= 3)
  std::size_t radius_k = 5;   // neighbours averaged for the radius (>= 1)
  float radius_scale = 1.0f;  // radii are multiplied by this (finite, > 0)
  RadiusRule radius_rule = RadiusRule::kCover;
  // Elliptic splats (cloud.axes, cloud.minor_radii) fitted to the same cells; kCover only.
  bool ellipses = false;
  // kCover only: move every splat centre along its normal onto the plane fitted to its point and
  // its sheet's neighbours (SplatShape::offset). On noisy scans the splats then lie on the
  // surface (a noise of σ along the normal leaves about σ/4 at k = 16) and cover it; positions
  // change, by about the noise.
  bool fit_centres = false;
  NormalMethod method = NormalMethod::kPca;
  NormalOrientation orient = NormalOrientation::kAuto;
  InputNormals input_normals = InputNormals::kAuto;
  // The zenith of kUp and of kVisibility's views (a unit vector; scans are +z up).
  Vec3f up{0, 0, 1};
  // Scanner position in FILE coordinates (the cloud's origin is subtracted). With kViewpoint and
  // no value here, the cloud's own viewpoint is used; neither present is an Error(kUsage).
  std::optional<std::array<double, 3>> viewpoint;
  // kVisibility: walls that hide what lies behind them from the views (the borders of a tile
  // where the survey goes on; visibility_votes.h), in the cloud's local frame.
  std::vector<VisibilityWall> walls;
  bool keep_duplicates = false;
  // Output the points in the spatial order the estimation runs in (Morton order, ties in the
  // input's order: thread-independent), not the input's: neighbours end up near each other in the
  // file, so the splat graph's neighbour lists encode smaller and every later stage reads memory in
  // order (build-splat-graph and segment-surfaces ran 2x faster on a shuffled 16M cloud).
  bool spatial_order = false;
  // No radius above max_radius_ratio × the median radius of its 8 nearest neighbours
  // (bound_radii.h); 0 = no bound. Default measured on clouds whose density varies 100x
  // (tests/unit/test_normals_bound_radii.cpp).
  float max_radius_ratio = kDefaultMaxRadiusRatio;
  // > 0: the neighbourhood phases run piece by piece, on pieces of about this many points with
  // halos (splat_pieces.h), holding one piece's working arrays at a time; the results are the
  // same. Method pca without fit_centres only (else Error(kUsage)).
  std::size_t piece_points = 0;
};

struct NormalReport {
  std::size_t input_points = 0;
  std::size_t output_points = 0;
  std::size_t duplicates_merged = 0;
  std::size_t degenerate_points = 0;  // k-neighbourhood degenerate, normal taken from a wider one
  std::size_t unresolved_points = 0;  // degenerate up to the widest neighbourhood: fallback normal
  std::size_t isolated_points = 0;    // no neighbour at a finite distance: the median radius
  std::size_t bounded_radii = 0;      // radii lowered to max_radius_ratio × their neighbours'
  std::size_t radii_over_bound = 0;   // still above it after bound_radii's last pass (0 normally)
  std::size_t widened_points = 0;     // method pca: normal taken from a 2k-row (widen_flat_normals.h)
  std::size_t refitted_points = 0;    // cover rule: splats fitted again from a wider row (open
                                      // cell) or after their normal changed
  double mean_centre_shift = 0;       // fit_centres: mean |offset| the centres moved by
  std::size_t flipped_points = 0;     // normals whose sign the orientation changed
  std::size_t components = 0;         // kNN-graph components (orient mst, visibility)
  // method pca: normals taken from a neighbour's face model, and the residual deviation that set
  // the band (select_face_normals.h).
  std::size_t face_selected = 0;
  float face_noise = 0;
  std::size_t two_face_points = 0;  // widened rows fitted as two parallel faces
  // {"method" (the one that ran), "reason" (why auto chose it, or "given"), "sheets",
  //  "by_evidence", "against_evidence", "seen" (visibility), "flipped"}; methods without a graph
  // leave out what they do not have.
  nlohmann::json orientation = nlohmann::json::object();
  // Normals taken from the input (kKeep) or from a mesh's faces, and the source: "estimated",
  // "input", "faces" or "input+estimated" / "faces+estimated".
  std::size_t given_normals = 0;
  std::string normals_source = "estimated";
  std::size_t input_had_normals = 0;  // points whose input normal was valid (kept or not)
  // Method robust: {"candidates", "refined", "threshold", "median_variation", "k", "noisy"}
  // (robust_normals.h); null for pca.
  nlohmann::json robust = nullptr;
  // With piece_points: {"pieces", "halo_points", "reruns"} (SplatPieces::Stats); else null.
  nlohmann::json pieces = nullptr;
  // Seconds per phase: "merge_duplicates", "order", "index", "normals_radii", "degenerate",
  // "robust", "refit_splats", "knn_rows", "bound_radii", "fit_centres", "orient", "reorder" (only
  // the phases that ran), and "total" (all of them).
  nlohmann::json timings = nlohmann::json::object();

  // {"input_points", "output_points", "duplicates_merged", "degenerate_points", ...,
  //  "timings_s": {...}, "points_per_s": output / total}.
  nlohmann::json to_json() const;
};

// Replaces cloud.normals and cloud.radii, and cloud.axes and cloud.minor_radii (cleared, or set
// with ellipses), and merges duplicates, in place. Throws Error(kUsage) for bad options (k < 3,
// radius_k < 1, radius_scale not finite and > 0, ellipses without kCover, viewpoint needed but
// absent),
// before any work, and Error(kBadInput) for a cloud of one distinct point (no radius can be
// estimated). An empty cloud is returned empty. Progress fractions cover the whole call.
NormalReport estimate_normals(SplatCloud& cloud, const NormalOptions& options,
                              const ProgressFn& progress = no_progress());

std::string method_name(NormalMethod m);
std::string orientation_name(NormalOrientation o);

// What kAuto resolves to for this cloud and options, and why (for the report); any other value
// is returned as it is, with the reason "given".
std::pair<NormalOrientation, std::string> choose_orientation(const SplatCloud& cloud,
                                                             const NormalOptions& options);

// The names of the per-point sensor position attributes of `cloud` (x, y, z: sensor_*, scanner_*
// or vp_*), or an empty array when it has none.
std::array<std::string, 3> sensor_attributes(const SplatCloud& cloud);

}  // namespace splatkit
