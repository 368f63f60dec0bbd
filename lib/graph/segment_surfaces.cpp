#include "graph/segment_surfaces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <stdexcept>

namespace splatkit::graph {

namespace {

// Rows per parallel task of the union-find.
constexpr std::size_t kRowBlock = 16384;

// A union-find shared by the threads. Every parent index is at most its node's own (a root is
// only ever linked below a smaller root, and path halving only shortcuts to an ancestor), so
// any value a thread reads is a valid ancestor: relaxed atomics suffice, there are no cycles, and
// the root of each tree ends up its lowest index whatever the order of the unions.
class ConcurrentForest {
 public:
  explicit ConcurrentForest(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0u);
  }

  uint32_t find(uint32_t i) {
    for (;;) {
      const uint32_t p = at(i).load(std::memory_order_relaxed);
      if (p == i) return i;
      const uint32_t grand = at(p).load(std::memory_order_relaxed);
      if (grand != p) at(i).store(grand, std::memory_order_relaxed);  // halve the path
      i = grand;
    }
  }

  void unite(uint32_t a, uint32_t b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a > b) std::swap(a, b);
      uint32_t expected = b;  // b may have been linked meanwhile: then retry from its new root
      if (at(b).compare_exchange_weak(expected, a, std::memory_order_relaxed)) return;
    }
  }

 private:
  std::atomic_ref<uint32_t> at(uint32_t i) { return std::atomic_ref<uint32_t>(parent_[i]); }
  std::vector<uint32_t> parent_;
};

}  // namespace

Segmentation segment_surfaces(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                              uint8_t sharp_mask) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument("segment_surfaces: one edge flag per neighbour entry needed");
  const std::size_t n = graph.num_points();
  // Union-find over the continuous edges, rows in index order within each block (the CSR arrays
  // are read front to back, which is what makes this faster than a breadth-first walk). The root
  // of a tree is always its lowest index, so the components and their ids are exactly those of
  // a breadth-first search started at the lowest unvisited index, for any thread count.
  ConcurrentForest forest(n);
  tbb::parallel_for(std::size_t{0}, (n + kRowBlock - 1) / kRowBlock, [&](std::size_t b) {
    for (std::size_t i = b * kRowBlock; i < std::min(n, (b + 1) * kRowBlock); ++i)
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        const uint32_t j = graph.neighbors[k];
        if (j > i && !(edge_flags[k] & sharp_mask)) forest.unite(static_cast<uint32_t>(i), j);
      }
  });
  Segmentation seg;
  seg.surface.resize(n);
  tbb::parallel_for(std::size_t{0}, (n + kRowBlock - 1) / kRowBlock, [&](std::size_t b) {
    for (std::size_t i = b * kRowBlock; i < std::min(n, (b + 1) * kRowBlock); ++i)
      seg.surface[i] = forest.find(static_cast<uint32_t>(i));
  });
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t root = seg.surface[i];
    if (root == i) {
      seg.surface[i] = seg.count();
      seg.sizes.push_back(0);
    } else {
      seg.surface[i] = seg.surface[root];  // root < i: already renumbered
    }
    ++seg.sizes[seg.surface[i]];
  }
  return seg;
}

}  // namespace splatkit::graph
