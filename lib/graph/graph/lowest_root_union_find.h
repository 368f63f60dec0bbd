// Union-find over splat indices where the root of a tree is always its lowest index, so that
// components come out in the order of their lowest member (the ids a breadth-first search from
// the lowest unvisited index gives). Used by segment_surfaces and segment_surfaces_robust.
// parent: #N, parent[i] = i initially; indices < N (unchecked).
#pragma once

#include <cstdint>
#include <vector>

namespace splatkit::graph {

// Root of i's tree, halving the path on the way (every node visited points to its grandparent).
inline uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Joins the trees of i and j, the lower root becoming the root.
inline void unite(std::vector<uint32_t>& parent, uint32_t i, uint32_t j) {
  const uint32_t a = find_root(parent, i), b = find_root(parent, j);
  if (a < b) parent[b] = a;
  if (b < a) parent[a] = b;
}

}  // namespace splatkit::graph
