// morton_order: the Morton (Z-order) sequence of a point set, the spatial order estimate-normals
// writes its splats in and build-spt builds over. Codes interleave 21 bits per axis over the
// bounding cube of the points (the cube's side is the box's largest extent; coordinates are
// quantised in double from the float positions, so a code depends only on the point and the box).
// Points sharing a code keep their input order. The order depends only on the point set and its
// input numbering: the same for any thread count, and reproducible piece by piece (a subset read
// in input order, coded over the whole set's box, sorts as it does within the whole).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/vec3.h"

namespace splatkit {

// Whether two positions are the same point for merge_duplicates (merge_duplicates.h): bit-equal
// coordinates, with -0 equal to +0. Such points have the same Morton code.
inline bool same_point(const Vec3f& a, const Vec3f& b) {
  auto bits = [](float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); };
  return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z);
}

// A point whose position (same_point) an earlier point has, and the earliest such point.
struct DuplicatePoint {
  uint32_t copy;
  uint32_t first;
  bool operator==(const DuplicatePoint&) const = default;
};

// Spreads the low 21 bits of v to every third bit.
inline uint64_t spread_morton_bits(uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// Morton codes (21 bits per axis, x highest) over the bounding cube of the box [l, h].
struct MortonFrame {
  static constexpr int kCodeBits = 63;
  Vec3f lo;
  double scale;
  MortonFrame(const Vec3f& l, const Vec3f& h) : lo(l) {
    const double extent = std::max({double(h.x) - l.x, double(h.y) - l.y, double(h.z) - l.z});
    scale = extent > 0 ? 2097151.0 / extent : 0.0;
  }
  // A NaN or infinite coordinate gives 0 on its axis (no undefined conversion).
  uint64_t code(const Vec3f& p) const {
    auto q = [&](float v, float l) {
      const double t = (double(v) - l) * scale;
      return t > 0 ? static_cast<uint64_t>(t < 2097151.0 ? t : 2097151.0) : uint64_t{0};
    };
    return spread_morton_bits(q(p.x, lo.x)) << 2 | spread_morton_bits(q(p.y, lo.y)) << 1 |
           spread_morton_bits(q(p.z, lo.z));
  }
};

// The points' numbers in Morton order over their own bounding box, ties by number: order[t] is
// the number of the t-th point. Runs in parallel; 16 bytes per point transiently.
std::vector<uint32_t> morton_order(std::span<const Vec3f> points);

// The same order, and `points` rearranged into it (points[t] becomes the old points[order[t]]).
// The keys carry the points (24 bytes per point; the input is freed once they hold it, so at most
// 40 bytes per point with the order and the output), so that nothing reads the points at random:
// a gather through the order would, and with the arrays paged from disk (--max-memory) random
// reads fault pages in faster than they can be dropped.
std::vector<uint32_t> morton_sort(std::vector<Vec3f>& points);

// The same, and in `copies` every point whose position an earlier point has, ascending by copy
// (what merge_duplicates finds): equal positions have equal codes, so the sorted keys hold them
// side by side, in input order. Nothing more is read than the sorted keys, in order.
std::vector<uint32_t> morton_sort(std::vector<Vec3f>& points, std::vector<DuplicatePoint>& copies);

}  // namespace splatkit
