#include "qsplat/build_qsplat_tree.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

#include "qsplat/fit_qsplat_nodes.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/select_rank.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::qsplat {

namespace {

struct Box {
  Vec3f lo, hi;
};

// Puts the leaf of rank m - b along the longest axis of `box` at m, the smaller ones before it,
// and cuts the box there into `left` and `right`.
void split_at(RankedPoint* pts, uint32_t b, uint32_t e, uint32_t m, const Box& box, Box& left,
              Box& right) {
  const int axis = longest_axis(box.lo, box.hi);
  select_rank(pts + b, pts + m, pts + e, axis);
  left = right = box;
  left.hi[axis] = right.lo[axis] = pts[m].coord(axis);
}

// How many leaves each child of a node of n leaves gets: none for a leaf (n = 1), n single
// leaves for n <= 4, else C = 4^k (the largest power of 4 below n) for every child but the last,
// which gets the rest; a rest below C/2 is shared evenly with the child before it, so that no
// child is much smaller than its siblings (a lone leaf under a large node would get a decoded
// sphere of at least 1/13 of that node's). Returns the number of children. Complete subtrees of
// 4^k leaves keep nodes at 4 children nearly everywhere, hence near 4/3 nodes per leaf.
int child_sizes(uint32_t n, uint32_t sizes[4], bool pairs = false) {
  if (n <= 1) return 0;
  if (pairs && n >= 3 && n <= 4) {
    sizes[0] = 2;
    sizes[1] = n - 2;
    return 2;
  }
  if (n <= 4) {
    for (uint32_t i = 0; i < n; ++i) sizes[i] = 1;
    return static_cast<int>(n);
  }
  uint32_t cap = 4;
  while (static_cast<uint64_t>(cap) * 4 < n) cap *= 4;
  const auto children = static_cast<int>((n + cap - 1) / cap);  // 2..4
  for (int k = 0; k + 1 < children; ++k) sizes[k] = cap;
  sizes[children - 1] = n - static_cast<uint32_t>(children - 1) * cap;
  if (sizes[children - 1] < cap / 2) {
    const uint32_t pair = sizes[children - 2] + sizes[children - 1];
    sizes[children - 1] = pair / 2;
    sizes[children - 2] = pair - pair / 2;
  }
  return children;
}

// Orders the leaves of node [b, e) (more than 4 of them, or 3–4 split in `pairs`) so that its
// children (child_sizes) are consecutive ranges: a cut along the longest axis of the leaves'
// bounding box, then a cut of each half along the longest axis of its part of that box.
void cut_node(RankedPoint* pts, uint32_t b, uint32_t e, bool pairs) {
  Box box;
  point_bounds(pts + b, pts + e, box.lo, box.hi);
  Box boxes[4];
  uint32_t sizes[4] = {0, 0, 0, 0};
  const int children = child_sizes(e - b, sizes, pairs);
  if (children == 2) {
    split_at(pts, b, e, b + sizes[0], box, boxes[0], boxes[1]);
    return;
  }
  const uint32_t half = b + sizes[0] + sizes[1];
  Box lo, hi;
  split_at(pts, b, e, half, box, lo, hi);
  if (children == 3) {
    split_at(pts, b, half, b + sizes[0], lo, boxes[0], boxes[1]);
    return;
  }
  auto left = [&] { split_at(pts, b, half, b + sizes[0], lo, boxes[0], boxes[1]); };
  auto right = [&] { split_at(pts, half, e, half + sizes[2], hi, boxes[2], boxes[3]); };
  if (e - b < (1u << 16)) {
    left();
    right();
  } else {  // the halves in parallel: at the top of the tree there are fewer nodes than threads
    tbb::parallel_invoke(left, right);
  }
}

}  // namespace

QSplatTree build_qsplat_tree(const QSplatLeaves& leaves, bool centroid_rule, bool measure) {
  QSplatTree t;
  const auto n = static_cast<uint32_t>(leaves.size());
  assert(n >= 2);
  SlotArray<RankedPoint> pts;  // uninitialised: filled below, its pages faulted in parallel
  pts.allocate(n);
  // With the leaves' box and largest radius, per chunk, combined in order.
  constexpr std::size_t kFillChunk = std::size_t{1} << 16;
  std::vector<Box> chunk_box(chunk_count(n, kFillChunk));
  std::vector<float> chunk_largest(chunk_box.size(), 0);
  for_each_chunk(n, kFillChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    Box box{leaves.positions[b], leaves.positions[b]};
    float largest = 0;
    for (std::size_t i = b; i < e; ++i) {
      pts[i] = RankedPoint::make(leaves.positions[i], static_cast<uint32_t>(i));
      for (int k = 0; k < 3; ++k) {
        box.lo[k] = std::min(box.lo[k], leaves.positions[i][k]);
        box.hi[k] = std::max(box.hi[k], leaves.positions[i][k]);
      }
      largest = std::max(largest, leaves.radii[i]);
    }
    chunk_box[c] = box;
    chunk_largest[c] = largest;
  });
  Box all = chunk_box[0];
  float largest = 0;
  for (std::size_t c = 0; c < chunk_box.size(); ++c) {
    for (int k = 0; k < 3; ++k) {
      all.lo[k] = std::min(all.lo[k], chunk_box[c].lo[k]);
      all.hi[k] = std::max(all.hi[k], chunk_box[c].hi[k]);
    }
    largest = std::max(largest, chunk_largest[c]);
  }
  const float pair_above = static_cast<float>(kPairLeavesAbove * 0.5 * norm(all.hi - all.lo));
  std::vector<uint32_t> rb{0}, size{n};  // each node's first leaf (in pts) and leaf count
  // Whether node i (3 or 4 leaves, ordered by its parent's cut) splits into pairs.
  const bool any_large = largest > pair_above;
  auto pairs = [&](uint32_t i) {
    if (!any_large || size[i] < 3 || size[i] > 4) return false;
    for (uint32_t k = rb[i]; k < rb[i] + size[i]; ++k)
      if (leaves.radii[pts[k].index()] > pair_above) return true;
    return false;
  };
  t.level_begin = {0, 1};
  t.first_child = {0};
  t.child_count = {0};
  // Fewer than 2n nodes (each interior node has 2 or more children): reserved, the arrays grow
  // level by level without copies or fresh pages beyond their final size, each level's pages
  // mapped in parallel before the zeroing.
  for (std::vector<uint32_t>* v : {&rb, &size, &t.first_child}) v->reserve(2 * std::size_t{n});
  t.child_count.reserve(2 * std::size_t{n});
  for (std::size_t l = 0;; ++l) {
    const uint32_t lb = t.level_begin[l], le = t.level_begin[l + 1];
    // The shape of the next level follows from the counts alone: place it first, then order the
    // leaves of every node in parallel. The children of each node follow the earlier nodes'
    // children: chunks of nodes count theirs, then place them after the earlier chunks'.
    constexpr std::size_t kNodeChunk = std::size_t{1} << 16;
    const std::size_t nodes = le - lb;
    std::vector<uint32_t> chunk_first(chunk_count(nodes, kNodeChunk) + 1, 0);
    for_each_chunk(nodes, kNodeChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
      uint32_t children = 0;
      for (std::size_t i = lb + b; i < lb + e; ++i) {
        uint32_t sizes[4];
        const int k = child_sizes(size[i], sizes, pairs(static_cast<uint32_t>(i)));
        t.child_count[i] = static_cast<uint8_t>(k);
        children += static_cast<uint32_t>(k);
      }
      chunk_first[c + 1] = children;
    });
    chunk_first[0] = le;
    for (std::size_t c = 1; c < chunk_first.size(); ++c) chunk_first[c] += chunk_first[c - 1];
    const uint32_t next = chunk_first.back();
    if (next == le) break;
    grown_in_parallel(rb, next);
    grown_in_parallel(size, next);
    for_each_chunk(nodes, kNodeChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
      uint32_t j = chunk_first[c];  // the next child's node
      for (std::size_t i = lb + b; i < lb + e; ++i) {
        uint32_t sizes[4];
        const int k = child_sizes(size[i], sizes, pairs(static_cast<uint32_t>(i)));
        t.first_child[i] = k > 0 ? j : 0;
        uint32_t at = rb[i];
        for (int q = 0; q < k; ++q, ++j) {
          rb[j] = at;
          size[j] = sizes[q];
          at += sizes[q];
        }
      }
    });
    tbb::parallel_for(tbb::blocked_range<uint32_t>(lb, le, 1), [&](const auto& r) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        const uint32_t b = rb[i], e = rb[i] + size[i];
        const bool split_pairs = e - b > 2 && e - b <= 4 && t.child_count[i] == 2;
        if (e - b > 4 || split_pairs)
          cut_node(pts.get(), b, e, split_pairs);
        else  // a node over its leaves: they follow in input order
          sort_short(pts.get() + b, pts.get() + e,
                     [](const RankedPoint& p) { return uint64_t{p.index()}; });
      }
    });
    grown_in_parallel(t.first_child, next);
    grown_in_parallel(t.child_count, next);
    t.level_begin.push_back(next);
  }
  const std::size_t m = t.first_child.size();
  // The node outputs are uninitialised: every entry is written, its page faulted in there, in
  // parallel, without a zeroing pass first.
  t.leaf.allocate(m);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 16), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i)
      t.leaf[i] = t.child_count[i] == 0 ? pts[rb[i]].index() : kNoLeaf;
  });
  fit_qsplat_nodes(t, leaves, centroid_rule, measure);
  return t;
}

}  // namespace splatkit::qsplat
