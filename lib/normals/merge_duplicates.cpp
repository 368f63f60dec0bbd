#include "normals/merge_duplicates.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <utility>

#include "splatkit/bucket_scatter.h"

namespace splatkit {

namespace {

// Bit pattern with -0 folded onto +0, so that positions equal as floats get equal keys.
uint32_t key_bits(float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); }

// 32 well-mixed bits of a position: equal positions hash equal; the rare collisions of different
// positions are sorted out by comparing the positions themselves.
uint64_t position_hash(const Vec3f& p) {
  uint64_t h = (uint64_t{key_bits(p.x)} << 32 | key_bits(p.y)) * 0x9E3779B97F4A7C15ull;
  h ^= (h >> 29) ^ (uint64_t{key_bits(p.z)} * 0xBF58476D1CE4E5B9ull);
  h *= 0x94D049BB133111EBull;
  return h >> 32;
}

template <typename T>
void compact(std::vector<T>& values, const std::vector<uint32_t>& kept) {
  if (values.empty()) return;
  for (std::size_t out = 0; out < kept.size(); ++out) values[out] = values[kept[out]];
  values.resize(kept.size());
  values.shrink_to_fit();
}

void compact(ExtraValues& values, const std::vector<uint32_t>& kept) {
  if (values.empty()) return;
  for (std::size_t out = 0; out < kept.size(); ++out) values.copy_value(out, kept[out]);
  values.resize(kept.size());
  values.shrink_to_fit();
}

// Every per-point array of the cloud but its positions, compacted to the kept points.
void compact_attributes(SplatCloud& cloud, const std::vector<uint32_t>& kept) {
  compact(cloud.normals, kept);
  compact(cloud.radii, kept);
  compact(cloud.axes, kept);
  compact(cloud.minor_radii, kept);
  compact(cloud.colors, kept);
  for (ExtraAttribute& extra : cloud.extras) compact(extra.values, kept);
}

// A point as the duplicate search carries it: its position travels with its number, so that the
// search reads the cloud once in order and then works bucket by bucket, never at random over the
// whole cloud (which, when the arrays are paged from disk, would fault pages in faster than they
// can be dropped).
struct Record {
  uint32_t hash;
  uint32_t index;
  Vec3f position;
};
static_assert(sizeof(Record) == 20);

using Duplicate = DuplicatePoint;  // copy: a point whose position an earlier point has; first: the
                                   // lowest index with that position

// Records are distributed by their hash's top bits into at most 4096 buckets: few enough that
// the scatter writes to a few thousand places at a time, many enough that a bucket and its table
// stay in cache (about 50 000 records per bucket at 200 M points).
constexpr int kMaxBucketBits = 12;
constexpr uint32_t kEmpty = 0xFFFFFFFF;

// Finds the duplicates of one bucket of records in ascending index order: each looks for an
// earlier first occurrence of its position in a small open-addressing table of first
// occurrences, and enters the table when there is none. The duplicates found are written over
// the front of the bucket (the k-th at byte 8k, in records that have been read by then);
// returns their number.
std::size_t resolve_bucket(Record* records, std::size_t n, std::vector<Record>& table) {
  const std::size_t mask = std::bit_ceil(std::max<std::size_t>(2 * n, 16)) - 1;
  table.assign(mask + 1, Record{0, kEmpty, {}});
  std::size_t found = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const Record r = records[t];
    std::size_t slot = r.hash & mask;
    uint32_t first = r.index;
    for (; table[slot].index != kEmpty; slot = (slot + 1) & mask)
      if (table[slot].hash == r.hash && same_point(table[slot].position, r.position)) {
        first = table[slot].index;
        break;
      }
    if (first == r.index)
      table[slot] = r;
    else {
      const Duplicate d{r.index, first};
      std::memcpy(reinterpret_cast<char*>(records) + sizeof d * found++, &d, sizeof d);
    }
  }
  return found;
}

// Every point whose position an earlier point has, with that earlier point's index, ascending by
// the copy's index. Records are scattered into buckets by their hash's top bits (bucket_scatter.h:
// two passes over the positions in order; each bucket in index order), and the buckets are
// resolved on their own, in parallel. Equal positions share a bucket, and the result does not
// depend on the thread count.
std::vector<Duplicate> find_duplicates(const std::vector<Vec3f>& positions) {
  const std::size_t n = positions.size();
  int bits = 0;
  while (bits < kMaxBucketBits && (n >> bits) > 256) ++bits;
  const std::size_t buckets = std::size_t{1} << bits;
  auto hash_of = [&](std::size_t i) { return static_cast<uint32_t>(position_hash(positions[i])); };
  auto bucket_of = [&](std::size_t i) {
    return bits == 0 ? 0 : std::size_t{hash_of(i) >> (32 - bits)};
  };
  const std::unique_ptr<Record[]> records(new Record[n]);
  const std::vector<std::size_t> start =
      bucket_scatter(n, buckets, bucket_of, [&](std::size_t i, std::size_t place) {
        records[place] = {hash_of(i), static_cast<uint32_t>(i), positions[i]};
      });
  std::vector<std::size_t> found(buckets);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 4), [&](const auto& r) {
    std::vector<Record> table;
    for (std::size_t d = r.begin(); d < r.end(); ++d)
      found[d] = resolve_bucket(records.get() + start[d], start[d + 1] - start[d], table);
  });
  std::size_t total = 0;
  for (std::size_t f : found) total += f;
  std::vector<Duplicate> duplicates(total);
  for (std::size_t d = 0, at = 0; d < buckets; at += found[d++])
    if (found[d] > 0)  // (duplicates.data() is null when there are none)
      std::memcpy(duplicates.data() + at, records.get() + start[d], sizeof(Duplicate) * found[d]);
  tbb::parallel_sort(duplicates.begin(), duplicates.end(),
                     [](const Duplicate& a, const Duplicate& b) { return a.copy < b.copy; });
  return duplicates;
}

}  // namespace

MergeResult merge_duplicates(SplatCloud& cloud, bool want_map) {
  const std::size_t n = cloud.size();
  MergeResult result;
  const std::vector<Duplicate> duplicates = find_duplicates(cloud.positions);
  result.merged = duplicates.size();
  if (result.merged == 0 && !want_map) return result;

  // One pass in index order: the kept points (input indices, ascending), and the map input index
  // -> output index when it is needed: a first occurrence's output slot is its rank among the
  // kept points, and every copy takes its first occurrence's, which precedes it.
  const bool map = want_map || (result.merged > 0 && !cloud.face_indices.empty());
  std::vector<uint32_t> representative(map ? n : 0);
  std::vector<uint32_t> kept;
  kept.reserve(n - result.merged);
  auto copy = duplicates.begin();
  for (std::size_t i = 0; i < n; ++i) {
    const bool is_copy = copy != duplicates.end() && copy->copy == i;
    if (map)
      representative[i] = is_copy ? representative[copy->first] : static_cast<uint32_t>(kept.size());
    if (is_copy)
      ++copy;
    else
      kept.push_back(static_cast<uint32_t>(i));
  }
  if (result.merged > 0) {
    compact(cloud.positions, kept);
    compact_attributes(cloud, kept);
    for (uint32_t& v : cloud.face_indices) v = representative[v];
  }
  if (want_map) result.representative = std::move(representative);
  return result;
}

std::size_t merge_sorted_duplicates(SplatCloud& cloud, std::vector<uint32_t>& order,
                                    const std::vector<DuplicatePoint>& copies) {
  if (copies.empty()) return 0;
  if (!cloud.face_indices.empty())
    throw std::logic_error("merge_sorted_duplicates: a cloud with faces is merged before sorting");
  // The kept points (input indices, ascending) and each one's number among them.
  const std::size_t n = order.size();
  constexpr uint32_t kCopy = 0xFFFFFFFF;
  std::vector<uint32_t> kept, number(n);
  kept.reserve(n - copies.size());
  auto copy = copies.begin();
  for (std::size_t i = 0; i < n; ++i) {
    if (copy != copies.end() && copy->copy == i) {
      ++copy;
      number[i] = kCopy;
      continue;
    }
    number[i] = static_cast<uint32_t>(kept.size());
    kept.push_back(static_cast<uint32_t>(i));
  }
  std::size_t out = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const uint32_t j = number[order[t]];
    if (j == kCopy) continue;
    order[out] = j;
    cloud.positions[out++] = cloud.positions[t];
  }
  order.resize(out);
  cloud.positions.resize(out);
  cloud.positions.shrink_to_fit();
  compact_attributes(cloud, kept);
  return copies.size();
}

}  // namespace splatkit
