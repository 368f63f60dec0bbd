// NeighborGraph: symmetric adjacency in compressed-row form, the shape every neighbour graph of
// splatkit takes (the spatial index's overlap search, the splat graph, the GRPH chunk).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace splatkit {

// Symmetric adjacency in compressed-row form: the neighbours of point i are
// neighbors[offsets[i] .. offsets[i + 1]), sorted ascending, never i itself. offsets has n + 1
// entries (offsets[0] = 0). Each unordered pair {i, j} appears twice, once in each row; the pairs
// i < j are the entries of row i greater than i.
struct NeighborGraph {
  std::vector<uint64_t> offsets;
  std::vector<uint32_t> neighbors;

  std::size_t num_points() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::span<const uint32_t> row(std::size_t i) const {
    return {neighbors.data() + offsets[i], neighbors.data() + offsets[i + 1]};
  }
};

}  // namespace splatkit
