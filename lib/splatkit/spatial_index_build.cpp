#include "splatkit/spatial_index.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "splatkit/error.h"
#include "splatkit/spatial_index_search.h"

namespace splatkit {

namespace {

using spatial_index_detail::is_finite;
using spatial_index_detail::kInf;

// Points per task when copying into and out of the build array.
constexpr std::size_t kCopyGrain = 65536;
// Below this many points a subtree is built on the current thread.
constexpr std::size_t kParallelBuildCutoff = 32768;

struct BuildPoint {
  float c[3];
  uint32_t id;
};

// Moves the points whose coordinate `axis` passes `take` to the front of [first, last), in one
// pass without data-dependent branches (a Lomuto partition that always swaps); returns the end
// of the front part.
template <typename Take>
BuildPoint* partition_points(BuildPoint* first, BuildPoint* last, int axis, Take take) {
  BuildPoint* out = first;
  for (BuildPoint* it = first; it != last; ++it) {
    const BuildPoint v = *it;
    *it = *out;
    *out = v;
    out += take(v.c[axis]) ? 1 : 0;
  }
  return out;
}

// Ranges longer than this are narrowed by sampled pivots first (select_nth).
constexpr std::ptrdiff_t kSampledSelect = 4096;
constexpr std::ptrdiff_t kSelectSample = 128;
constexpr std::ptrdiff_t kSelectGap = 10;

// std::nth_element by coordinate `axis` (the same contract) with the branch-free partition above
// and a median-of-three pivot. When the pivot is the smallest coordinate its copies are split off
// instead, so runs of equal coordinates still make progress; after a generous number of rounds
// (an adversarial input) it hands over to std::nth_element.
void select_nth(BuildPoint* first, BuildPoint* nth, BuildPoint* last, int axis) {
  auto less = [axis](const BuildPoint& a, const BuildPoint& b) { return a.c[axis] < b.c[axis]; };
  int rounds = 2 * std::bit_width(static_cast<std::size_t>(last - first)) + 8;
  // Large ranges (after Floyd and Rivest): two pivots from an even sample bracket nth's rank, so
  // that the range shrinks to the few per cent between them in about 1.5 passes, where a
  // median-of-three pivot takes about 3 passes to find a median.
  while (last - first > kSampledSelect) {
    if (rounds-- == 0) return std::nth_element(first, nth, last, less);
    const std::ptrdiff_t size = last - first, rank = nth - first;
    float sample[kSelectSample];
    for (std::ptrdiff_t i = 0; i < kSelectSample; ++i)
      sample[i] = first[(2 * i + 1) * size / (2 * kSelectSample)].c[axis];
    std::sort(sample, sample + kSelectSample);
    const std::ptrdiff_t k = rank * kSelectSample / size;
    const float lo = sample[std::max<std::ptrdiff_t>(k - kSelectGap, 0)];
    const float hi = sample[std::min<std::ptrdiff_t>(k + kSelectGap, kSelectSample - 1)];
    // Both parts are shorter than the range: lo and hi are coordinates of points in it.
    BuildPoint* below = partition_points(first, last, axis, [lo](float v) { return v < lo; });
    if (nth < below) {
      last = below;
      continue;
    }
    BuildPoint* upto = partition_points(below, last, axis, [hi](float v) { return v <= hi; });
    if (nth >= upto) {
      first = upto;
      continue;
    }
    if (lo == hi) return;  // [below, upto) holds one coordinate: nth is in place
    first = below;
    last = upto;
  }
  while (last - first > 16) {
    if (rounds-- == 0) return std::nth_element(first, nth, last, less);
    float a = first->c[axis], b = first[(last - first) / 2].c[axis], c = last[-1].c[axis];
    const float pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
    BuildPoint* below = partition_points(first, last, axis, [pivot](float v) { return v < pivot; });
    if (nth < below) {
      last = below;
      continue;
    }
    if (below > first) {
      first = below;
      continue;
    }
    // The pivot is the smallest coordinate: split off its copies (at least one) instead.
    BuildPoint* equal =
        partition_points(first, last, axis, [pivot](float v) { return v == pivot; });
    if (nth < equal) return;
    first = equal;
  }
  std::sort(first, last, less);
}

}  // namespace

// Builds the subtree `node` over pts[begin, end): tight box, then a median split on its widest
// axis at the position where the implicit layout puts the boundary between its two halves.
struct SpatialIndex::Builder {
  std::vector<BuildPoint>& pts;
  std::vector<Box>& boxes;
  const std::vector<uint32_t>& leaf_start;
  uint32_t first_leaf;

  void build(uint32_t node, uint32_t leaf_lo, uint32_t leaf_hi) {
    std::size_t begin = leaf_start[leaf_lo], end = leaf_start[leaf_hi];
    Box box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
    for (std::size_t i = begin; i < end; ++i) {
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = std::min(box.lo[a], pts[i].c[a]);
        box.hi[a] = std::max(box.hi[a], pts[i].c[a]);
      }
    }
    boxes[node] = box;
    if (node >= first_leaf) return;

    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
    }
    uint32_t leaf_mid = leaf_lo + (leaf_hi - leaf_lo) / 2;
    std::size_t mid = leaf_start[leaf_mid];
    select_nth(pts.data() + begin, pts.data() + mid, pts.data() + end, axis);
    auto left = [&] { build(2 * node + 1, leaf_lo, leaf_mid); };
    auto right = [&] { build(2 * node + 2, leaf_mid, leaf_hi); };
    if (end - begin >= kParallelBuildCutoff) {
      tbb::parallel_invoke(left, right);
    } else {
      left();
      right();
    }
  }
};

SpatialIndex::SpatialIndex(std::span<const Vec3f> points, std::size_t max_leaf_size) {
  if (max_leaf_size == 0) throw std::invalid_argument("SpatialIndex: max_leaf_size must be > 0");
  if (points.size() > std::size_t{kNone} - 1) {
    throw std::invalid_argument("SpatialIndex: more than 2^32 - 2 points");
  }
  const std::size_t n = points.size();
  std::vector<BuildPoint> pts(n);
  std::atomic<bool> all_finite{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kCopyGrain), [&](const auto& r) {
    bool finite = true;
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const Vec3f& p = points[i];
      finite &= is_finite(p);
      pts[i] = {{p.x, p.y, p.z}, static_cast<uint32_t>(i)};
    }
    if (!finite) all_finite = false;
  });
  if (!all_finite) {
    const std::size_t i = static_cast<std::size_t>(
        std::find_if_not(points.begin(), points.end(), is_finite) - points.begin());
    throw Error(ErrorKind::kBadInput,
                "spatial index: point " + std::to_string(i) + " has a non-finite coordinate");
  }

  // 2^depth leaves of equal size (within one point), so the layout needs no pointers.
  uint32_t leaves = 1;
  while (n > std::size_t{leaves} * max_leaf_size) leaves *= 2;
  first_leaf_ = leaves - 1;
  leaf_start_.resize(leaves + 1);
  for (uint32_t j = 0; j <= leaves; ++j)
    leaf_start_[j] = static_cast<uint32_t>(uint64_t{j} * n / leaves);
  boxes_.resize(2 * std::size_t{leaves} - 1);
  Builder{pts, boxes_, leaf_start_, first_leaf_}.build(0, 0, leaves);

  // Padded by three so that four-wide loads at the end of the last leaf stay in bounds.
  xs_.assign(n + 3, 0.0f);
  ys_.assign(n + 3, 0.0f);
  zs_.assign(n + 3, 0.0f);
  ids_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kCopyGrain), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      xs_[i] = pts[i].c[0];
      ys_[i] = pts[i].c[1];
      zs_[i] = pts[i].c[2];
      ids_[i] = pts[i].id;
    }
  });
}

std::size_t SpatialIndex::memory_bytes() const {
  return (xs_.capacity() + ys_.capacity() + zs_.capacity()) * sizeof(float) +
         ids_.capacity() * sizeof(uint32_t) + boxes_.capacity() * sizeof(Box) +
         leaf_start_.capacity() * sizeof(uint32_t);
}

}  // namespace splatkit
