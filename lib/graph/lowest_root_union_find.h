// Union-find over splat indices where the root of a tree is always its lowest index, so that
// components come out in the order of their lowest member (the ids a breadth-first search from
// the lowest unvisited index gives). Used by segment_surfaces and segment_surfaces_robust.
// parent: #N, parent[i] = i initially; indices < N (unchecked).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {

// Root of i's tree, halving the path on the way (every node visited points to its grandparent).
inline uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Root of i's tree, leaving the tree as it is: safe from several threads once the joining is
// done.
inline uint32_t root_of(const std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i];
  return i;
}

// Joins the trees of i and j, the lower root becoming the root; returns it.
inline uint32_t unite(std::vector<uint32_t>& parent, uint32_t i, uint32_t j) {
  const uint32_t a = find_root(parent, i), b = find_root(parent, j);
  if (a < b) parent[b] = a;
  if (b < a) parent[a] = b;
  return std::min(a, b);
}

// find_root and unite for several threads at once (every access to parent atomic). The higher
// of two roots always hangs under the lower (by a compare-and-swap that fails if the higher one
// stopped being a root meanwhile, and is then retried), so every parent points to a lower index
// of its own tree, a stale read still names an ancestor, and path halving may race: the components,
// and each tree's root (its lowest index), come out the same in any order of the joins.
inline uint32_t find_root_shared(std::vector<uint32_t>& parent, uint32_t i) {
  for (;;) {
    std::atomic_ref<uint32_t> at(parent[i]);
    const uint32_t p = at.load(std::memory_order_relaxed);
    if (p == i) return i;
    const uint32_t g = std::atomic_ref<uint32_t>(parent[p]).load(std::memory_order_relaxed);
    if (g != p) at.store(g, std::memory_order_relaxed);
    i = g;
  }
}

inline void unite_shared(std::vector<uint32_t>& parent, uint32_t i, uint32_t j) {
  for (;;) {
    uint32_t a = find_root_shared(parent, i), b = find_root_shared(parent, j);
    if (a == b) return;
    if (a > b) std::swap(a, b);
    uint32_t expected = b;
    if (std::atomic_ref<uint32_t>(parent[b]).compare_exchange_weak(expected, a,
                                                                   std::memory_order_relaxed))
      return;
    i = a;
    j = b;
  }
}

// Joins i and j for every edge the rows give, in parallel: edges(i, fn) calls fn(j) for the
// edges (i, j) to be joined, each with j > i (required: a j below i could belong to another
// chunk), and must give the same edges when called again. Each chunk of rows joins the edges that
// stay inside it on its own (a chunk's trees only hold its own splats, so the chunks never touch
// the same entry); the edges that leave their chunk are joined afterwards by a second walk over
// the rows, in parallel too, with the atomic find_root_shared / unite_shared (enumerating them
// again costs less than keeping them: in a cloud in no spatial order nearly every edge leaves its
// chunk, 8 bytes each, and that walk through random rows was a serial third of segmenting 16M
// splats). The components, and so the roots, do not depend on the thread count or the order of
// the joins. parent: as above, all splats their own root.
template <class Edges>
void unite_rows(std::vector<uint32_t>& parent, Edges&& edges) {
  constexpr std::size_t kChunk = 16384;  // rows per task
  const std::size_t n = parent.size();
  for_each_chunk(n, kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      uint32_t root = find_root(parent, uint32_t(i));
      edges(i, [&](uint32_t j) {
        if (j >= end) return;  // joined below
        // Rows are joined in ascending order, so every tree with more than one splat has its
        // root at or below i < j: a j that is its own root is alone, and hangs from i's root
        // like a j that is already there (the common cases, without a search).
        const uint32_t p = parent[j];
        if (p == root || p == j)
          parent[j] = root;
        else
          root = unite(parent, root, j);
      });
    }
  });
  for_each_chunk(n, kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      edges(i, [&](uint32_t j) {
        if (j >= end) unite_shared(parent, uint32_t(i), j);
      });
  });
}

}  // namespace splatkit::graph
