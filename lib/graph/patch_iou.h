// patch_iou: how well a segmentation recovers known patches — for every true patch, the surface
// that matches it best by intersection over union, |P ∩ S| / |P ∪ S| over splat counts. The
// measure of scripts/bench/segmentation-quality.sh and tests/unit/test_graph_patch_iou.cpp
// ("every patch recovered with IoU >= 0.95").
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace splatkit::graph {

struct PatchMatch {
  uint32_t patch = 0;         // true label
  uint64_t size = 0;          // splats with this label
  uint32_t surface = 0;       // best surface (0xFFFFFFFF when the patch meets no surface)
  uint64_t surface_size = 0;  // splats of that surface
  uint64_t overlap = 0;       // splats in both
  double iou = 0;             // overlap / (size + surface_size - overlap)
};

// truth, surfaces: #N labels each (any uint32 values; surface 0xFFFFFFFF = no surface, which
// never matches). One entry per distinct true label, ascending; ties between surfaces go to the
// lower surface id. Throws std::invalid_argument when the sizes differ. O(N log N).
std::vector<PatchMatch> patch_iou(std::span<const uint32_t> truth,
                                  std::span<const uint32_t> surfaces);

// The fraction of the matches with iou >= threshold (1 for no matches).
double fraction_recovered(std::span<const PatchMatch> matches, double threshold);

}  // namespace splatkit::graph
