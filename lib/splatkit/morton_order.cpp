#include "splatkit/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <cmath>
#include <memory>
#include <type_traits>
#include <utility>

#include "splatkit/splat_cloud.h"

namespace splatkit {

namespace {

struct Key {
  uint64_t code;
  uint32_t index;
  bool operator<(const Key& o) const { return code != o.code ? code < o.code : index < o.index; }
};

// A key that carries its point, for morton_sort (24 bytes: the point fills Key's padding).
struct PointKey {
  uint64_t code;
  uint32_t index;
  Vec3f point;
  bool operator<(const PointKey& o) const {
    return code != o.code ? code < o.code : index < o.index;
  }
};
static_assert(sizeof(PointKey) == 24);

// Keys go first to buckets by their top bits (a counting pass over fixed blocks), then each
// bucket is sorted on its own; buckets larger than this are sorted in parallel.
constexpr int kTopBits = 12;
constexpr std::size_t kBuckets = std::size_t{1} << kTopBits;
constexpr std::size_t kParallelSortSize = std::size_t{1} << 20;

// The Morton order of `points`; with a PointKey, also rewrites *sorted (the vector `points` views)
// as the points in that order, from the keys: it is freed once the keys hold the points, and no
// pass reads the points at random.
template <typename K>
std::vector<uint32_t> sort_by_code(std::span<const Vec3f> points, std::vector<Vec3f>* sorted) {
  const std::size_t n = points.size();
  const Bounds box = compute_bounds(points);
  const MortonFrame frame(box.min, box.max);
  const std::size_t block = std::max<std::size_t>(std::size_t{1} << 16, (n + 63) / 64);
  const std::size_t blocks = (n + block - 1) / block;
  auto top = [](uint64_t code) { return code >> (MortonFrame::kCodeBits - kTopBits); };
  // Per block and bucket: the count, then the block's first place in the bucket.
  std::vector<std::size_t> first(blocks * kBuckets, 0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t* c = first.data() + b * kBuckets;
    for (std::size_t i = b * block, e = std::min(n, i + block); i < e; ++i)
      ++c[top(frame.code(points[i]))];
  });
  std::vector<std::size_t> start(kBuckets + 1);
  std::size_t sum = 0;
  for (std::size_t d = 0; d < kBuckets; ++d) {
    start[d] = sum;
    for (std::size_t b = 0; b < blocks; ++b) sum += std::exchange(first[b * kBuckets + d], sum);
  }
  start[kBuckets] = sum;
  const std::unique_ptr<K[]> keys(new K[n]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t* next = first.data() + b * kBuckets;
    for (std::size_t i = b * block, e = std::min(n, i + block); i < e; ++i) {
      const uint64_t code = frame.code(points[i]);
      K& key = keys[next[top(code)]++];
      key.code = code;
      key.index = static_cast<uint32_t>(i);
      if constexpr (std::is_same_v<K, PointKey>) key.point = points[i];
    }
  });
  if constexpr (std::is_same_v<K, PointKey>)
    std::vector<Vec3f>().swap(*sorted);  // the keys hold the points: `points` is gone from here on
  tbb::parallel_for(std::size_t{0}, kBuckets, [&](std::size_t d) {
    K* b = keys.get() + start[d];
    K* e = keys.get() + start[d + 1];
    if (static_cast<std::size_t>(e - b) > kParallelSortSize)
      tbb::parallel_sort(b, e);
    else
      std::sort(b, e);
  });
  std::vector<uint32_t> order(n);
  if constexpr (std::is_same_v<K, PointKey>) sorted->resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
    for (std::size_t t = r.begin(); t < r.end(); ++t) {
      order[t] = keys[t].index;
      if constexpr (std::is_same_v<K, PointKey>) (*sorted)[t] = keys[t].point;
    }
  });
  return order;
}

}  // namespace

std::vector<uint32_t> morton_order(std::span<const Vec3f> points) {
  return sort_by_code<Key>(points, nullptr);
}

std::vector<uint32_t> morton_sort(std::vector<Vec3f>& points) {
  return sort_by_code<PointKey>(points, &points);
}

}  // namespace splatkit
