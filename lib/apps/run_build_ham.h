// build-ham's work, callable without the command line: stream a heightmap (TIFF, PNG, EXR, SRTM
// .hgt or headerless RAW), fill its voids, compute the height acceleration map
// (terrain/compute_ham.h) and write its per-tile records as an EXR (formats/ham.md), optionally
// the full-resolution HAM as a tiled float EXR, and a JSON report.
#pragma once

#include <optional>
#include <string>

#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit::apps {

struct BuildHamOptions {
  StagePaths paths;              // IN: heightmap ('-' only with raw); OUT: .exr or '-'
  int64_t tile = 64;             // tile side, texels
  std::string ham_full;          // full-resolution HAM (.exr), or empty
  std::optional<double> nodata;  // overrides the file's own no-data value
  double z_scale = 1;            // heights are multiplied by it first
  std::string raw;               // "W,H,TYPE[,ENDIAN]": IN is headerless RAW
};

// Throws Error(kUsage) for bad options or paths, Error(kBadInput) for an unreadable or malformed
// heightmap, Error(kUnsupported) when the OpenImageIO module is missing, Error(kOutput).
StageSummary run_build_ham(const BuildHamOptions& options,
                           const ProgressFn& progress = no_progress());

}  // namespace splatkit::apps
