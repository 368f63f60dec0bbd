#include "qsplat/build_qsplat_tree.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "qsplat/enclose_spheres.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/sized_in_parallel.h"
#include "splatkit/slot_array.h"

namespace splatkit::qsplat {

namespace {

// A leaf's centre and index as two words, (x, y) and (z, leaf): the partition below stores and
// reloads points, and a 16-byte load of a point just stored as 12 + 4 bytes would miss the store
// forwarding (a stall per point).
struct Point {
  uint64_t xy, zl;
  static Point make(const Vec3f& p, uint32_t leaf) {
    uint32_t u[3];
    std::memcpy(u, &p, sizeof u);
    return {uint64_t{u[1]} << 32 | u[0], uint64_t{leaf} << 32 | u[2]};
  }
  uint32_t bits(int axis) const {
    return static_cast<uint32_t>(axis == 0 ? xy : axis == 1 ? xy >> 32 : zl);
  }
  float coord(int axis) const { return std::bit_cast<float>(bits(axis)); }
  Vec3f position() const { return {coord(0), coord(1), coord(2)}; }
  uint32_t leaf() const { return static_cast<uint32_t>(zl >> 32); }
};

// Ranges at least this long are cut by sampled pivots (select_rank).
constexpr std::size_t kSampledSelect = std::size_t{1} << 13;

struct Box {
  Vec3f lo, hi;
};

// The order leaves are cut in along axis A, as one integer: the coordinate's float bits made to
// sort as unsigned integers (-0 as +0, so that equal floats tie), then the leaf index. Keys are
// unique, so the ranks, and so the leaves of every child, do not depend on how they are found.
template <int A>
uint64_t cut_key(const Point& q) {
  uint32_t u = q.bits(A);
  u = u == 0x80000000u ? 0 : u;
  u ^= (u >> 31) != 0 ? 0xFFFFFFFFu : 0x80000000u;
  return uint64_t{u} << 32 | q.leaf();
}

// Moves the points of [first, last) whose key is below `pivot` to the front, in one branch-free
// Lomuto pass (the comparisons of a cut are coin flips, which a branch mispredicts half the
// time), and returns the end of that front part.
template <int A>
Point* partition_below(Point* first, Point* last, uint64_t pivot) {
  Point* i = first;
  for (Point* j = first; j < last; ++j) {
    const Point q = *j;
    const bool less = cut_key<A>(q) < pivot;
    *j = *i;
    *i = q;
    i += less;
  }
  return i;
}

// Puts the point of rank nth - first in [first, last) by cut_key<A> at nth, smaller keys before
// it, larger after. A large range is cut by two pivots drawn from a sample of its keys, which
// bracket the rank with near certainty [Floyd75]: one pass keeps the side that holds nth, the
// next pass over that side leaves a sliver of a few percent around it (about n + min(k, n - k)
// moves, against about 2.75 n for quickselect with a median-of-3 pivot, which finishes the small
// ranges). A range that shrinks too slowly is left to std::nth_element, whose worst case is
// n log n.
template <int A>
void select_rank(Point* first, Point* nth, Point* last) {
  const auto before = [](const Point& p, const Point& q) { return cut_key<A>(p) < cut_key<A>(q); };
  int budget = 2 * std::bit_width(static_cast<std::size_t>(last - first));
  std::vector<uint64_t> sample;
  while (last - first > 16) {
    if (budget-- == 0) {
      std::nth_element(first, nth, last, before);
      return;
    }
    const std::size_t n = static_cast<std::size_t>(last - first);
    const std::size_t k = static_cast<std::size_t>(nth - first);
    if (n >= kSampledSelect) {
      // n^(2/3) keys at even strides; pivots 2 sqrt(s) sample ranks either side of k's (four
      // standard deviations of the sample rank of the true k-th key).
      const auto s = static_cast<std::size_t>(std::cbrt(static_cast<double>(n)) *
                                              std::cbrt(static_cast<double>(n)));
      sample.resize(s);
      for (std::size_t i = 0; i < s; ++i) sample[i] = cut_key<A>(first[i * n / s]);
      const auto spread = static_cast<std::size_t>(2 * std::sqrt(static_cast<double>(s))) + 1;
      const std::size_t at = k * s / n;
      const std::size_t lo = at > spread ? at - spread : 0, hi = std::min(s - 1, at + spread);
      std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(hi),
                       sample.end());
      const uint64_t upper = sample[hi];
      std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(lo),
                       sample.begin() + static_cast<std::ptrdiff_t>(hi));
      const uint64_t lower = sample[lo];
      // The pivot beyond k on the longer side first: the second pass runs over the shorter.
      const auto keep = [&](uint64_t pivot) {
        Point* i = partition_below<A>(first, last, pivot);
        (nth < i ? last : first) = i;
      };
      if (2 * k < n) {
        keep(upper);
        keep(lower);
      } else {
        keep(lower);
        keep(upper);
      }
      continue;
    }
    const uint64_t a = cut_key<A>(*first), b = cut_key<A>(first[n / 2]), c = cut_key<A>(last[-1]);
    const uint64_t pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
    // [first, i) < pivot <= [i, last): both sides keep at least one of a, b, c, so both shrink.
    Point* i = partition_below<A>(first, last, pivot);
    (nth < i ? last : first) = i;
  }
  std::sort(first, last, before);
}

// Puts the leaf of rank m - b along the longest axis of `box` at m, the smaller ones before it,
// and cuts the box there into `left` and `right`.
void split_at(std::vector<Point>& pts, uint32_t b, uint32_t e, uint32_t m, const Box& box,
              Box& left, Box& right) {
  const Vec3f ext = box.hi - box.lo;
  const int axis = ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
  Point *const first = pts.data() + b, *const nth = pts.data() + m, *const last = pts.data() + e;
  if (axis == 0) select_rank<0>(first, nth, last);
  if (axis == 1) select_rank<1>(first, nth, last);
  if (axis == 2) select_rank<2>(first, nth, last);
  left = right = box;
  left.hi[axis] = right.lo[axis] = pts[m].coord(axis);
}

// How many leaves each child of a node of n leaves gets: none for a leaf (n = 1), n single
// leaves for n <= 4, else C = 4^k (the largest power of 4 below n) for every child but the last,
// which gets the rest; a rest below C/2 is shared evenly with the child before it, so that no
// child is much smaller than its siblings (a lone leaf under a large node would get a decoded
// sphere of at least 1/13 of that node's). Returns the number of children. Complete subtrees of
// 4^k leaves keep nodes at 4 children nearly everywhere, hence near 4/3 nodes per leaf.
int child_sizes(uint32_t n, uint32_t sizes[4]) {
  if (n <= 1) return 0;
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

// The bounding box of the centres of pts[b, e): in parallel chunks for the few largest nodes
// (minima and maxima do not depend on the order they are taken in).
Box bounds(const std::vector<Point>& pts, uint32_t b, uint32_t e) {
  // Four lanes per point, x, y, z and the leaf index's bits (ignored), in a generic vector: the
  // minima and maxima of a point's lanes in one instruction each.
  static_assert(std::endian::native == std::endian::little, "the lanes follow Point's bytes");
  using Lanes = float __attribute__((vector_size(16)));
  auto serial = [&](uint32_t from, uint32_t to) {
    Lanes lo, hi;
    std::memcpy(&lo, &pts[from], sizeof lo);
    hi = lo;
    for (uint32_t i = from + 1; i < to; ++i) {
      Lanes v;
      std::memcpy(&v, &pts[i], sizeof v);
      lo = v < lo ? v : lo;
      hi = hi < v ? v : hi;
    }
    return Box{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  };
  constexpr std::size_t kChunk = std::size_t{1} << 18;
  if (e - b < 2 * kChunk) return serial(b, e);
  std::vector<Box> part(chunk_count(e - b, kChunk));
  for_each_chunk(e - b, kChunk, [&](std::size_t c, std::size_t lo, std::size_t hi) {
    part[c] = serial(b + static_cast<uint32_t>(lo), b + static_cast<uint32_t>(hi));
  });
  Box box = part[0];
  for (const Box& q : part)
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = std::min(box.lo[k], q.lo[k]);
      box.hi[k] = std::max(box.hi[k], q.hi[k]);
    }
  return box;
}

// Orders the leaves of node [b, e) (more than 4 of them) so that its children (child_sizes) are
// consecutive ranges: a cut along the longest axis of the leaves' bounding box, then a cut of
// each half along the longest axis of its part of that box.
void cut_node(std::vector<Point>& pts, uint32_t b, uint32_t e) {
  const Box box = bounds(pts, b, e);
  Box boxes[4];
  uint32_t sizes[4] = {0, 0, 0, 0};
  const int children = child_sizes(e - b, sizes);
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

double cosine(const Vec3f& a, const Vec3f& b) {
  return std::clamp(static_cast<double>(dot(a, b)), -1.0, 1.0);
}

}  // namespace

QSplatTree build_qsplat_tree(const QSplatLeaves& leaves, bool centroid_rule,
                             bool measure_centroid_rule) {
  QSplatTree t;
  const auto n = static_cast<uint32_t>(leaves.size());
  std::vector<Point> pts;
  sized_in_parallel(pts, n);  // its pages mapped in parallel, not by the zeroing
  for_each_chunk(n, std::size_t{1} << 16, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      pts[i] = Point::make(leaves.positions[i], static_cast<uint32_t>(i));
  });
  std::vector<uint32_t> rb{0}, size{n};  // each node's first leaf (in pts) and leaf count
  t.level_begin = {0, 1};
  t.first_child = {0};
  t.child_count = {0};
  // Fewer than 2n nodes (each interior node has 2 or more children): reserved, the arrays grow
  // level by level without copies or fresh pages beyond their final size.
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
        const int k = child_sizes(size[i], sizes);
        t.child_count[i] = static_cast<uint8_t>(k);
        children += static_cast<uint32_t>(k);
      }
      chunk_first[c + 1] = children;
    });
    chunk_first[0] = le;
    for (std::size_t c = 1; c < chunk_first.size(); ++c) chunk_first[c] += chunk_first[c - 1];
    const uint32_t next = chunk_first.back();
    if (next == le) break;
    rb.resize(next);
    size.resize(next);
    for_each_chunk(nodes, kNodeChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
      uint32_t j = chunk_first[c];  // the next child's node
      for (std::size_t i = lb + b; i < lb + e; ++i) {
        uint32_t sizes[4];
        const int k = child_sizes(size[i], sizes);
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
        if (e - b > 4)
          cut_node(pts, b, e);
        else  // a node over its leaves: they follow in input order
          std::sort(pts.begin() + b, pts.begin() + e,
                    [](const Point& p, const Point& q) { return p.leaf() < q.leaf(); });
      }
    });
    t.first_child.resize(next, 0);
    t.child_count.resize(next, 0);
    t.level_begin.push_back(next);
  }
  const std::size_t m = t.first_child.size();
  const bool color = !leaves.colors.empty();
  // The parents' sums, for interior nodes only (uninitialised: the pages of the bottom level,
  // all leaves, are never touched); then the outputs, for every node. Fresh pages cost more than
  // the zeros written into them: the outputs are made side by side.
  SlotArray<Sphere> centroid;
  SlotArray<Vec3f> normal;
  SlotArray<float> cone;
  SlotArray<std::array<uint8_t, 3>> rgb;
  normal.allocate(m);
  cone.allocate(m);
  if (color) rgb.allocate(m);
  if (measure_centroid_rule) centroid.allocate(m);
  tbb::parallel_invoke(
      [&] {
        t.leaf.resize(m);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1 << 16), [&](const auto& r) {
          for (std::size_t i = r.begin(); i < r.end(); ++i)
            t.leaf[i] = t.child_count[i] == 0 ? pts[rb[i]].leaf() : kNoLeaf;
        });
      },
      [&] { t.spheres.resize(m); },
      [&] {
        t.normal_codes.resize(m);
        t.cones.resize(m);
        if (color) t.colors.resize(m);
      });
  // Bottom up, level by level: each interior node from its children, a leaf child's values
  // taken from the input there (its outputs written, nothing kept for it). The input is in any
  // order: the leaves of the nodes a few places ahead are prefetched.
  const uint8_t leaf_cone = static_cast<uint8_t>(encode_cone(0));
  for (std::size_t l = t.levels() - 1; l-- > 0;) {  // the deepest level holds only leaves
    const uint32_t lb = t.level_begin[l], le = t.level_begin[l + 1];
    tbb::parallel_for(tbb::blocked_range<uint32_t>(lb, le, 1024), [&](const auto& r) {
      constexpr uint32_t kAhead = 4;  // nodes, of up to 4 children each
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        if (i + kAhead < le)
          for (int k = 0; k < t.child_count[i + kAhead]; ++k) {
            const uint32_t ahead = t.leaf[t.first_child[i + kAhead] + static_cast<uint32_t>(k)];
            if (ahead == kNoLeaf) continue;
            __builtin_prefetch(&leaves.normals[ahead]);
            __builtin_prefetch(&leaves.radii[ahead]);
            if (color) __builtin_prefetch(&leaves.colors[ahead]);
          }
        const int c = t.child_count[i];
        if (c == 0) continue;  // a leaf: its parent writes it
        const uint32_t f = t.first_child[i];
        Vec3f child_normal[4];
        float child_cone[4];
        std::array<uint8_t, 3> child_rgb[4];
        Sphere child_centroid[4];
        for (int k = 0; k < c; ++k) {
          const uint32_t q = f + static_cast<uint32_t>(k), j = t.leaf[q];
          if (j == kNoLeaf) {
            child_normal[k] = normal[q];
            child_cone[k] = cone[q];
            if (color) child_rgb[k] = rgb[q];
            if (measure_centroid_rule) child_centroid[k] = centroid[q];
            continue;
          }
          t.spheres[q] = {pts[rb[q]].position(), leaves.radii[j]};
          child_normal[k] = leaves.normals[j];
          child_cone[k] = 0;
          child_centroid[k] = t.spheres[q];
          t.normal_codes[q] = static_cast<uint16_t>(encode_normal(child_normal[k]));
          t.cones[q] = leaf_cone;
          if (color) {
            child_rgb[k] = leaves.colors[j];
            t.colors[q] = encode_rgb565(child_rgb[k][0], child_rgb[k][1], child_rgb[k][2]);
          }
        }
        t.spheres[i] = enclose_spheres(&t.spheres[f], c, centroid_rule);
        if (measure_centroid_rule) centroid[i] = enclose_spheres(child_centroid, c, true);
        Vec3f sum{0, 0, 0};
        for (int k = 0; k < c; ++k) sum += child_normal[k];
        normal[i] = squared_norm(sum) > 0 ? normalized(sum) : child_normal[0];
        if (color) {
          std::array<int, 3> acc{0, 0, 0};
          for (int k = 0; k < c; ++k)
            for (int j = 0; j < 3; ++j) acc[j] += child_rgb[k][j];
          for (int j = 0; j < 3; ++j) rgb[i][j] = static_cast<uint8_t>((acc[j] + c / 2) / c);
        }
        t.normal_codes[i] = static_cast<uint16_t>(encode_normal(normal[i]));
        const Vec3f& dn = decode_normal(t.normal_codes[i]);
        // The widest child: angle to its normal plus its own cone. Among children without a cone
        // (leaves, mostly) the widest is the one of least cosine: one arc cosine for them all.
        double theta = 0, least_cos = 2;
        for (int k = 0; k < c; ++k) {
          const double cos = cosine(dn, decode_normal(t.normal_codes[f + k]));
          if (child_cone[k] == 0)
            least_cos = std::min(least_cos, cos);
          else
            theta = std::max(theta, std::acos(cos) + child_cone[k]);
        }
        if (least_cos <= 1) theta = std::max(theta, std::acos(least_cos));
        cone[i] = static_cast<float>(theta + 1e-6);  // float rounding of the sum, upwards
        t.cones[i] = static_cast<uint8_t>(encode_cone(cone[i]));
        if (color) t.colors[i] = encode_rgb565(rgb[i][0], rgb[i][1], rgb[i][2]);
      }
    });
  }
  double sum = 0, sum_centroid = 0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < m; ++i)
    if (t.child_count[i] > 0) {
      sum += t.spheres[i].radius;
      if (measure_centroid_rule) sum_centroid += centroid[i].radius;
      ++interior;
    }
  t.mean_interior_radius = interior ? sum / interior : 0;
  t.mean_interior_radius_centroid = interior ? sum_centroid / interior : 0;
  return t;
}

}  // namespace splatkit::qsplat
