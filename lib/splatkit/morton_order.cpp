#include "splatkit/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <cmath>
#include <memory>

#include "splatkit/splat_cloud.h"

namespace splatkit {

namespace {

struct Key {
  uint64_t code;
  uint32_t index;
  bool operator<(const Key& o) const { return code != o.code ? code < o.code : index < o.index; }
};

// Keys go first to buckets by their top bits (a counting pass over fixed blocks), then each
// bucket is sorted on its own; buckets larger than this are sorted in parallel.
constexpr int kTopBits = 12;
constexpr std::size_t kBuckets = std::size_t{1} << kTopBits;
constexpr std::size_t kParallelSortSize = std::size_t{1} << 20;

}  // namespace

std::vector<uint32_t> morton_order(std::span<const Vec3f> points) {
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
  const std::unique_ptr<Key[]> keys(new Key[n]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t* next = first.data() + b * kBuckets;
    for (std::size_t i = b * block, e = std::min(n, i + block); i < e; ++i) {
      const uint64_t code = frame.code(points[i]);
      keys[next[top(code)]++] = {code, static_cast<uint32_t>(i)};
    }
  });
  tbb::parallel_for(std::size_t{0}, kBuckets, [&](std::size_t d) {
    Key* b = keys.get() + start[d];
    Key* e = keys.get() + start[d + 1];
    if (static_cast<std::size_t>(e - b) > kParallelSortSize)
      tbb::parallel_sort(b, e);
    else
      std::sort(b, e);
  });
  std::vector<uint32_t> order(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
    for (std::size_t t = r.begin(); t < r.end(); ++t) order[t] = keys[t].index;
  });
  return order;
}

}  // namespace splatkit
