// The shuffle table of AVX2 "left-pack" (AVX2 has no compress instruction): byte k of
// kLaneCompress[mask] is the lane of the k-th set bit of mask, so a permutation by those bytes
// packs the selected lanes of an eight-wide vector to its front. Shared by the SIMD paths of
// SpatialIndex and graph::sphere_overlap_graph.
#pragma once

#include <array>
#include <cstdint>

namespace splatkit {

inline constexpr std::array<uint64_t, 256> kLaneCompress = [] {
  std::array<uint64_t, 256> table{};
  for (unsigned mask = 0; mask < 256; ++mask) {
    int out = 0;
    for (int lane = 0; lane < 8; ++lane)
      if (mask >> lane & 1) table[mask] |= uint64_t(lane) << (8 * out++);
  }
  return table;
}();

}  // namespace splatkit
