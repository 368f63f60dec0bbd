#include "splatkit/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

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

// Keys per block of the last pass (and of the search for copies).
constexpr std::size_t kPassBlock = std::size_t{1} << 16;
// Runs of equal codes longer than this are searched for copies by sorting them.
constexpr std::size_t kShortRun = 32;

// The copies among keys[begin, end), a run of equal codes in index order, appended to `out`.
void run_copies(const PointKey* keys, std::size_t begin, std::size_t end,
                std::vector<DuplicatePoint>& out) {
  const std::size_t size = end - begin;
  if (size <= kShortRun) {
    // Each key against the run's earlier first occurrences (bit j: keys[begin + j] is one).
    uint32_t firsts = 0;
    for (std::size_t u = 0; u < size; ++u) {
      uint32_t first = keys[begin + u].index;
      for (uint32_t f = firsts; f != 0; f &= f - 1) {
        const std::size_t v = static_cast<std::size_t>(std::countr_zero(f));
        if (same_point(keys[begin + v].point, keys[begin + u].point)) {
          first = keys[begin + v].index;
          break;
        }
      }
      if (first == keys[begin + u].index)
        firsts |= uint32_t{1} << u;
      else
        out.push_back({keys[begin + u].index, first});
    }
    return;
  }
  // (A long run: many copies of a few points.) Sorted by coordinate bits, then index, each group
  // of equal positions starts with its first occurrence.
  struct Item {
    std::array<uint32_t, 3> bits;
    uint32_t index;
  };
  auto bits = [](float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); };
  std::vector<Item> items(size);
  for (std::size_t u = 0; u < size; ++u) {
    const PointKey& k = keys[begin + u];
    items[u] = {{bits(k.point.x), bits(k.point.y), bits(k.point.z)}, k.index};
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.bits != b.bits ? a.bits < b.bits : a.index < b.index;
  });
  for (std::size_t u = 1, first = 0; u < size; ++u) {
    if (items[u].bits != items[first].bits)
      first = u;
    else
      out.push_back({items[u].index, items[first].index});
  }
}

// The copies among the sorted keys, ascending by copy. Each block takes the runs of equal codes
// that start in it (a run may reach into the next block, which skips it).
std::vector<DuplicatePoint> find_copies(const PointKey* keys, std::size_t n) {
  const std::size_t blocks = (n + kPassBlock - 1) / kPassBlock;
  std::vector<std::vector<DuplicatePoint>> found(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t t = b * kPassBlock;
    const std::size_t end = std::min(n, t + kPassBlock);
    while (t > 0 && t < end && keys[t].code == keys[t - 1].code) ++t;
    while (t < end) {
      std::size_t run_end = t + 1;
      while (run_end < n && keys[run_end].code == keys[t].code) ++run_end;
      if (run_end - t > 1) run_copies(keys, t, run_end, found[b]);
      t = run_end;
    }
  });
  std::vector<DuplicatePoint> copies;
  for (const std::vector<DuplicatePoint>& f : found)
    copies.insert(copies.end(), f.begin(), f.end());
  std::sort(copies.begin(), copies.end(),
            [](const DuplicatePoint& a, const DuplicatePoint& b) { return a.copy < b.copy; });
  return copies;
}

// The Morton order of `points`; with a PointKey, also rewrites *sorted (the vector `points` views)
// as the points in that order, from the keys: it is freed once the keys hold the points, and no
// pass reads the points at random. copies (PointKey only): null, or receives the copies.
template <typename K>
std::vector<uint32_t> sort_by_code(std::span<const Vec3f> points, std::vector<Vec3f>* sorted,
                                   std::vector<DuplicatePoint>* copies = nullptr) {
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
  if constexpr (std::is_same_v<K, PointKey>)
    if (copies) *copies = find_copies(keys.get(), n);
  std::vector<uint32_t> order(n);
  if constexpr (std::is_same_v<K, PointKey>) sorted->resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kPassBlock), [&](const auto& r) {
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

std::vector<uint32_t> morton_sort(std::vector<Vec3f>& points, std::vector<DuplicatePoint>& copies) {
  return sort_by_code<PointKey>(points, &points, &copies);
}

}  // namespace splatkit
