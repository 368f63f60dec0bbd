// Union-find over splat indices where the root of a tree is always its lowest index, so that
// components come out in the order of their lowest member (the ids a breadth-first search from
// the lowest unvisited index gives). Used by segment_surfaces and segment_surfaces_robust.
// parent: #N, parent[i] = i initially; indices < N (unchecked).
//
// Safe to call from several threads on the same parent array: every access is a relaxed atomic
// one; a link is a compare-and-swap on a root, so two threads never link the same root, and a
// path is only shortened on nodes that are no longer roots (which nothing else writes but other
// shortenings, each to an ancestor). The components, and so the roots, do not depend on the
// order or the threads of the calls.
#pragma once

#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

namespace splatkit::graph {

// Root of i's tree, halving the path on the way (a node visited points to its grandparent).
inline uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  for (;;) {
    const uint32_t p = std::atomic_ref<uint32_t>(parent[i]).load(std::memory_order_relaxed);
    if (p == i) return i;
    const uint32_t g = std::atomic_ref<uint32_t>(parent[p]).load(std::memory_order_relaxed);
    if (g == p) return p;
    std::atomic_ref<uint32_t>(parent[i]).store(g, std::memory_order_relaxed);
    i = g;
  }
}

// Joins the trees of i and j, the lower root becoming the root; returns it (an ancestor of both
// by the time it is used, when other threads link meanwhile). i may be any node of its tree, so
// a caller joining one splat to many passes the last result back as i.
inline uint32_t unite(std::vector<uint32_t>& parent, uint32_t i, uint32_t j) {
  // The common case in a row-by-row pass: j already hangs from the node passed back.
  if (std::atomic_ref<uint32_t>(parent[j]).load(std::memory_order_relaxed) == i) return i;
  for (;;) {
    uint32_t a = find_root(parent, i), b = find_root(parent, j);
    if (a == b) return a;
    if (a < b) std::swap(a, b);  // a, the higher root, goes under b
    uint32_t expected = a;
    if (std::atomic_ref<uint32_t>(parent[a]).compare_exchange_strong(expected, b,
                                                                     std::memory_order_relaxed))
      return b;
    i = a;  // a was linked meanwhile: again from its new root
    j = b;
  }
}

}  // namespace splatkit::graph
