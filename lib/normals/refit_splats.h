// refit_splats: the refit phase of estimate_normals (estimate_normals.h). Fits the splats of
// `points` again from rows of k points, one kNN query each: points whose normal changed after
// phase 3, and points whose cover cell the phase-3 row left open. Every normal is final by then, so
// the neighbours' normals tell the sheets apart too (fit_splat in pca_normals_and_radii.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "normals/estimate_normals.h"
#include "splatkit/spatial_index.h"

namespace splatkit {

// index: built over cloud.positions (#N). points: the indices to refit. sq_reach (empty, or #N):
// receives, for each listed point, the squared distance of its row's last entry. Runs in parallel.
void refit_splats(const SpatialIndex& index, SplatCloud& cloud, const NormalOptions& o,
                  std::span<const uint32_t> points, std::size_t k, std::span<float> sq_reach = {});

}  // namespace splatkit
