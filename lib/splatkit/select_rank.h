// Rank selection of points along one axis, for hierarchies cut at the median or at other ranks
// (the QSplat tree, the chunk hierarchy of occlusion culling).
//
// Points travel with their index as two 8-byte words, so that a cut compares and moves them
// without reading the cloud at random. The order along axis A is (coordinate, index), with -0
// equal to +0: keys are unique, so the points on either side of a rank, and so every hierarchy
// cut by ranks, do not depend on how the rank is found or on the thread count.
#pragma once

#include <algorithm>
#include <cassert>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "splatkit/for_each_chunk.h"
#include "splatkit/vec3.h"

namespace splatkit {

// A point and its index as two words, (x, y) and (z, index): a cut stores and reloads points,
// and a 16-byte load of a point just stored as 12 + 4 bytes would miss the store forwarding (a
// stall per point).
struct RankedPoint {
  uint64_t xy, zi;
  static RankedPoint make(const Vec3f& p, uint32_t index) {
    uint32_t u[3];
    std::memcpy(u, &p, sizeof u);
    return {uint64_t{u[1]} << 32 | u[0], uint64_t{index} << 32 | u[2]};
  }
  uint32_t bits(int axis) const {
    return static_cast<uint32_t>(axis == 0 ? xy : axis == 1 ? xy >> 32 : zi);
  }
  float coord(int axis) const { return std::bit_cast<float>(bits(axis)); }
  Vec3f position() const { return {coord(0), coord(1), coord(2)}; }
  uint32_t index() const { return static_cast<uint32_t>(zi >> 32); }
};

// Sorts a short range (at most kShortRange points) by key(point), a uint64_t that differs between
// the points: each point's place is the count of smaller keys, found without a branch, where a
// sort's comparisons of keys in no order would mispredict about half the time.
inline constexpr std::size_t kShortRange = 16;
template <typename Key>
void sort_short(RankedPoint* first, RankedPoint* last, Key key) {
  const auto n = static_cast<std::size_t>(last - first);
  assert(n <= kShortRange);
  uint64_t k[kShortRange];
  RankedPoint sorted[kShortRange];
  for (std::size_t i = 0; i < n; ++i) k[i] = key(first[i]);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t below = 0;
    for (std::size_t j = 0; j < n; ++j) below += k[j] < k[i];
    sorted[below] = first[i];
  }
  std::copy(sorted, sorted + n, first);
}

namespace rank_detail {

// Ranges at least this long are cut by sampled pivots.
inline constexpr std::size_t kSampledSelect = std::size_t{1} << 13;

// The order along axis A as one integer: the coordinate's float bits made to sort as unsigned
// integers (-0 as +0, so that equal floats tie), then the index.
template <int A>
uint64_t cut_key(const RankedPoint& q) {
  uint32_t u = q.bits(A);
  u = u == 0x80000000u ? 0 : u;
  // Negative values flip all bits, others only the sign bit: an arithmetic shift, not a branch
  // (the signs of a cloud around the origin are coin flips, which a branch mispredicts).
  u ^= static_cast<uint32_t>(static_cast<int32_t>(u) >> 31) | 0x80000000u;
  return uint64_t{u} << 32 | q.index();
}

// Moves the points of [first, last) whose key is below `pivot` to the front, in one branch-free
// Lomuto pass (the comparisons of a cut are coin flips, which a branch mispredicts half the
// time), and returns the end of that front part.
template <int A>
RankedPoint* partition_below(RankedPoint* first, RankedPoint* last, uint64_t pivot) {
  RankedPoint* i = first;
  for (RankedPoint* j = first; j < last; ++j) {
    const RankedPoint q = *j;
    const bool less = cut_key<A>(q) < pivot;
    *j = *i;
    *i = q;
    i += less;
  }
  return i;
}

// select_rank for one axis.
template <int A>
void select_rank_on(RankedPoint* first, RankedPoint* nth, RankedPoint* last) {
  const auto before = [](const RankedPoint& p, const RankedPoint& q) {
    return cut_key<A>(p) < cut_key<A>(q);
  };
  int budget = 2 * std::bit_width(static_cast<std::size_t>(last - first));
  std::vector<uint64_t> sample;
  while (static_cast<std::size_t>(last - first) > kShortRange) {
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
        RankedPoint* i = partition_below<A>(first, last, pivot);
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
    RankedPoint* i = partition_below<A>(first, last, pivot);
    (nth < i ? last : first) = i;
  }
  sort_short(first, last, cut_key<A>);
}

}  // namespace rank_detail

// Puts the point of rank nth - first in [first, last) along `axis` (0, 1 or 2) at nth, the
// smaller ones before it (in no particular order), the larger after. A large range is cut by two
// pivots drawn from a sample of its keys, which bracket the rank with near certainty [Floyd75]:
// one pass keeps the side that holds nth, the next pass over that side leaves a sliver of a few
// percent around it (about n + min(k, n - k) moves, against about 2.75 n for quickselect with a
// median-of-3 pivot, which finishes the small ranges). A range that shrinks too slowly is left
// to std::nth_element, whose worst case is n log n.
inline void select_rank(RankedPoint* first, RankedPoint* nth, RankedPoint* last, int axis) {
  if (axis == 0) rank_detail::select_rank_on<0>(first, nth, last);
  if (axis == 1) rank_detail::select_rank_on<1>(first, nth, last);
  if (axis == 2) rank_detail::select_rank_on<2>(first, nth, last);
}

// The axis along which the box [lo, hi] is longest (the first of equal ones).
inline int longest_axis(const Vec3f& lo, const Vec3f& hi) {
  const Vec3f ext = hi - lo;
  return ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
}

namespace rank_detail {

// point_bounds of one thread, four lanes at a time: x, y, z and the index's bits (ignored); the
// minima and maxima of a point's lanes in one instruction each.
inline void serial_bounds(const RankedPoint* first, const RankedPoint* last, Vec3f& lo,
                          Vec3f& hi) {
  static_assert(std::endian::native == std::endian::little, "the lanes follow the point's bytes");
  using Lanes = float __attribute__((vector_size(16)));
  Lanes l, h;
  std::memcpy(&l, first, sizeof l);
  h = l;
  for (const RankedPoint* p = first + 1; p < last; ++p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    l = v < l ? v : l;
    h = h < v ? v : h;
  }
  lo = {l[0], l[1], l[2]};
  hi = {h[0], h[1], h[2]};
}

}  // namespace rank_detail

// The bounding box [lo, hi] of the positions of [first, last) (non-empty): in parallel chunks
// for the few largest ranges (minima and maxima do not depend on the order they are taken in).
inline void point_bounds(const RankedPoint* first, const RankedPoint* last, Vec3f& lo,
                         Vec3f& hi) {
  constexpr std::size_t kChunk = std::size_t{1} << 18;
  const auto n = static_cast<std::size_t>(last - first);
  if (n < 2 * kChunk) return rank_detail::serial_bounds(first, last, lo, hi);
  std::vector<Vec3f> part_lo(chunk_count(n, kChunk)), part_hi(part_lo.size());
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    rank_detail::serial_bounds(first + b, first + e, part_lo[c], part_hi[c]);
  });
  lo = part_lo[0];
  hi = part_hi[0];
  for (std::size_t c = 1; c < part_lo.size(); ++c)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], part_lo[c][k]);
      hi[k] = std::max(hi[k], part_hi[c][k]);
    }
}

}  // namespace splatkit
