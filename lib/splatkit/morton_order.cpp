#include "splatkit/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <cmath>
#include <memory>
#include <type_traits>
#include <utility>

#include "splatkit/bucket_scatter.h"
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

// Keys go first to buckets by their top bits (bucket_scatter.h), then each bucket is sorted on
// its own; buckets larger than this are sorted in parallel.
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
  auto top = [](uint64_t code) { return code >> (MortonFrame::kCodeBits - kTopBits); };
  const std::unique_ptr<K[]> keys(new K[n]);
  const std::vector<std::size_t> start = bucket_scatter(
      n, kBuckets, [&](std::size_t i) { return top(frame.code(points[i])); },
      [&](std::size_t i, std::size_t place) {
        K& key = keys[place];
        key.code = frame.code(points[i]);
        key.index = static_cast<uint32_t>(i);
        if constexpr (std::is_same_v<K, PointKey>) key.point = points[i];
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
