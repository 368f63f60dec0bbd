// bound_radii: no splat larger than `ratio` times its neighbourhood's splats. A point at the edge
// of a dense region, a stray point or a thin sparse patch gets a cover radius far larger than the
// splats around it — a blob in front of the surface; this caps it.
//
// Each pass sets r_i = min(r_i, ratio × median of the radii of i's k nearest other points) (the
// median of the radii as the pass found them, so passes are order-independent), scaling the
// minor radius of an ellipse by the same factor. Passes repeat, at most max_passes times, until
// one caps nothing; then every radius is within ratio × its neighbours' final median. Radii stay
// positive when they all were (fill_isolated_radii runs first). Deterministic for any thread
// count. Cost per pass: one streamed kNN pass (k + 1 per row), or a pass over rows found ahead,
// and one more to count the radii still over their bound only when max_passes run out before a
// pass caps nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "splatkit/spatial_index.h"

namespace splatkit {

// Neighbours whose median radius bounds a splat (estimate_normals).
inline constexpr std::size_t kBoundRadiiK = 8;
// estimate_normals' second bound, over a wider neighbourhood: no radius above kWideBoundRatio ×
// the median of its kWideBoundK nearest (a sparse cluster smaller than that is bounded by the
// surface around it), in at most kWideBoundPasses passes (bound_wide_radii).
inline constexpr std::size_t kWideBoundK = 32;
inline constexpr float kWideBoundRatio = 3.0f;
inline constexpr std::size_t kWideBoundPasses = 2;

struct BoundRadiiResult {
  std::size_t capped = 0;  // points whose radius was lowered (counted once)
  std::size_t passes = 0;
  std::size_t over = 0;  // radii still above ratio × their neighbours' median after the last pass
};

// radii: #N, positive; minor_radii: #N or empty. ratio >= 1 (smaller values are a usage error the
// caller rejects); k >= 1.
BoundRadiiResult bound_radii(const SpatialIndex& index, std::vector<float>& radii,
                             std::vector<float>& minor_radii, float ratio, std::size_t k = 8,
                             std::size_t max_passes = 4);

// The same passes with the medians from `medians(radii)` (#N each): for a cloud processed in
// pieces (splats_in_pieces.h).
BoundRadiiResult bound_radii(
    const std::function<std::vector<float>(const std::vector<float>&)>& medians,
    std::vector<float>& radii, std::vector<float>& minor_radii, float ratio,
    std::size_t max_passes = 4);

// The bound of bound_radii over the k nearest other points of the points whose radius exceeds
// ratio × the cloud's 2nd-percentile radius only (a smaller splat is no blob to speak of; on
// even sampling that leaves a few per cent of the points to query, so the wider row costs
// little; 4.7 % on an i.i.d. torus), each pass reading the radii as the previous one left them.
// A later pass queries a candidate again only when a candidate's radius changed within its k-th
// neighbour's distance (the others' medians cannot have changed): the passes after the first cost
// little. positions: #N, the index's points. Counts as bound_radii does (`over`: among the
// candidates).
BoundRadiiResult bound_wide_radii(const SpatialIndex& index, std::span<const Vec3f> positions,
                                  std::vector<float>& radii, std::vector<float>& minor_radii,
                                  float ratio, std::size_t k, std::size_t max_passes);

// The median of the radii of each point's k nearest other points (#N). sq_reach (empty, or #N)
// receives the squared distance of each point's k-th nearest other point.
std::vector<float> neighbour_median_radii(const SpatialIndex& index,
                                          const std::vector<float>& radii, std::size_t k,
                                          std::span<float> sq_reach = {});

// The same medians from kNN rows found ahead (#N rows of `width` >= k entries: each point's
// nearest other points, nearest first, as orient_knn_rows gives them): the rows of a kNN query of
// more than k + 1 points start with the k + 1 nearest, so the medians are the same.
std::vector<float> row_median_radii(std::span<const uint32_t> rows, std::size_t width,
                                    const std::vector<float>& radii, std::size_t k);

}  // namespace splatkit
