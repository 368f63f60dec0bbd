// splat_radius: the disc radius of a splat from its kNN row, by the rule of [IvoMSc] ch. 6
// (docs/references.md): the mean Euclidean distance to its `radius_k` nearest neighbours, so that
// neighbouring splats overlap.
//
// `sq_dists` is one row as SpatialIndex::knn_all gives it: column 0 is the point itself (distance
// 0), then neighbours by ascending squared distance; +inf marks unused slots (a cloud smaller than
// the row). Neighbours at distance 0 (exact duplicates kept with --keep-duplicates) are skipped:
// they would shrink the disc without covering any more surface. The mean is over the first
// `radius_k` remaining neighbours, or over as many as the row holds; 0 when it holds none (a lone
// point). Never NaN for finite input.
#pragma once

#include <cstddef>
#include <span>

namespace splatkit {

float splat_radius(std::span<const float> sq_dists, std::size_t radius_k);

}  // namespace splatkit
