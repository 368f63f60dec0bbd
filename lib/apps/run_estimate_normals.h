// estimate-normals' work, callable without the command line: read a point cloud (any format),
// estimate a unit normal and a splat radius per point (normals/estimate_normals.h), write .ply or
// .splk with the provenance, and optionally a JSON report.
#pragma once

#include <optional>
#include <string>

#include "apps/stage.h"
#include "apps/stage_types.h"

#include "normals/estimate_normals.h"
#include "normals/remove_outliers.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct EstimateNormalsOptions {
  StagePaths paths;  // OUT: .ply or .splk (or "-": .splk), unless `format` says
  ReadOptions read;  // read.columns: text input's column layout
  // k, radius_k, radius_scale, keep_duplicates; method, orient and viewpoint come from the texts
  // below.
  NormalOptions normals;
  std::string radius = "cover";  // --radius: cover or mean-knn
  std::string splat = "circle";  // --splat: circle or ellipse
  std::string method = "pca";    // pca | robust
  // auto | mst | up | viewpoint | sensor | visibility | none; empty: auto, or viewpoint with
  // `viewpoint`.
  std::string orient;
  std::string normals_from = "auto";  // --normals: auto | estimate | keep
  std::string viewpoint;              // "x,y,z" in file coordinates, or empty
  std::string format;                 // ply | splk, or empty: OUT's extension
  // --keep-order: the input's order, not the spatial one (sets normals.spatial_order).
  bool keep_order = false;
  // --outliers: "" or "none", or passes "sor[:K,SIGMA]" / "radius[:R,N]" / "plane[:K,T]" joined
  // by '+', each applied to what the previous kept ("sor" alone: the default passes,
  // sor:12,3+sor:6,3.5+plane:16,6; normals/remove_outliers.h); the points removed before
  // anything else, all passes' written to `outliers_out` when it is not empty.
  std::string outliers;
  std::string outliers_out;
  // --max-memory: the cloud is processed in pieces that fit the limit (piece_points), and the
  // tool's frame spills its large arrays to --tmp-dir (splatkit/spill_arena.h).
  MemoryLimit memory;
};

// Parses --outliers into its passes (none for "" and "none"); throws Error(kUsage) naming the
// option.
std::vector<OutlierOptions> parse_outliers(const std::string& text);

// Throws Error(kUsage) for bad or conflicting options and unusable paths (before reading),
// Error(kBadInput) / Error(kUnsupported) for the input, Error(kOutput) when writing fails,
// Error(kOutOfMemory) naming the step.
StageSummary run_estimate_normals(const EstimateNormalsOptions& options,
                                  const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
