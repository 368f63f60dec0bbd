#include "normals/merge_duplicates.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>

namespace splatkit {

namespace {

// Bit pattern with -0 folded onto +0, so that positions equal as floats get equal keys.
uint32_t key_bits(float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); }

bool same_position(const Vec3f& a, const Vec3f& b) {
  return key_bits(a.x) == key_bits(b.x) && key_bits(a.y) == key_bits(b.y) &&
         key_bits(a.z) == key_bits(b.z);
}

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

// Sets first[] for one bucket of keys in ascending index order: each point looks for an earlier
// first occurrence with its position in a small open-addressing table (slots hold key positions;
// the first occurrences only), and enters the table when there is none.
void resolve_bucket(const std::vector<Vec3f>& positions, const uint64_t* keys, std::size_t n,
                    std::vector<uint32_t>& first, std::vector<uint32_t>& table) {
  constexpr uint32_t kEmpty = 0xFFFFFFFF;
  const std::size_t mask = std::bit_ceil(std::max<std::size_t>(2 * n, 16)) - 1;
  table.assign(mask + 1, kEmpty);
  for (std::size_t t = 0; t < n; ++t) {
    const uint32_t hash = static_cast<uint32_t>(keys[t] >> 32);
    const uint32_t i = static_cast<uint32_t>(keys[t]);
    first[i] = i;
    std::size_t slot = hash & mask;
    for (; table[slot] != kEmpty; slot = (slot + 1) & mask) {
      const uint64_t other = keys[table[slot]];
      const uint32_t j = static_cast<uint32_t>(other);
      if (other >> 32 == hash && same_position(positions[j], positions[i])) {
        first[i] = j;
        break;
      }
    }
    if (first[i] == i) table[slot] = static_cast<uint32_t>(t);
  }
}

// first[i] = the lowest index whose position equals point i's (i itself for a first occurrence).
// Keys (hash << 32 | index) are distributed by the hash's top bits into buckets of ~256 (one
// stable counting pass, so each bucket is in index order), then each bucket is resolved on its
// own, in parallel: equal positions share a bucket, and the result does not depend on the thread
// count.
std::vector<uint32_t> first_occurrences(const std::vector<Vec3f>& positions) {
  const std::size_t n = positions.size();
  int bits = 0;
  while (bits < 20 && (n >> bits) > 256) ++bits;
  const std::size_t buckets = std::size_t{1} << bits;
  std::vector<uint32_t> hashes(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i)
      hashes[i] = static_cast<uint32_t>(position_hash(positions[i]));
  });
  std::vector<std::size_t> start(buckets + 1, 0);
  const int shift = 32 - bits;
  auto bucket_of = [&](uint32_t h) { return bits == 0 ? 0 : std::size_t{h >> shift}; };
  for (uint32_t h : hashes) ++start[bucket_of(h) + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<uint64_t> keys(n);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      keys[fill[bucket_of(hashes[i])]++] = uint64_t{hashes[i]} << 32 | i;
  }
  std::vector<uint32_t>().swap(hashes);  // (`= {}` would keep the capacity)
  std::vector<uint32_t> first(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 16), [&](const auto& r) {
    std::vector<uint32_t> table;
    for (std::size_t b = r.begin(); b < r.end(); ++b)
      resolve_bucket(positions, keys.data() + start[b], start[b + 1] - start[b], first, table);
  });
  return first;
}

}  // namespace

MergeResult merge_duplicates(SplatCloud& cloud, bool want_map) {
  const std::size_t n = cloud.size();
  MergeResult result;
  std::vector<uint32_t> first = first_occurrences(cloud.positions);

  std::vector<uint32_t> kept;  // input indices of the output points, ascending
  for (std::size_t i = 0; i < n; ++i)
    if (first[i] == i) kept.push_back(static_cast<uint32_t>(i));
  result.merged = n - kept.size();
  if (result.merged == 0 && !want_map) return result;

  // Reuse `first` as the map input index -> output index: a first occurrence's output slot is its
  // rank among the kept points, and every copy points at its first occurrence, which precedes it.
  for (std::size_t i = 0, out = 0; i < n; ++i)
    first[i] = first[i] == i ? static_cast<uint32_t>(out++) : first[first[i]];

  if (result.merged > 0) {
    compact(cloud.positions, kept);
    compact(cloud.normals, kept);
    compact(cloud.radii, kept);
    compact(cloud.axes, kept);
    compact(cloud.minor_radii, kept);
    compact(cloud.colors, kept);
    for (ExtraAttribute& extra : cloud.extras) compact(extra.values, kept);
    for (uint32_t& v : cloud.face_indices) v = first[v];
  }
  if (want_map) result.representative = std::move(first);
  return result;
}

}  // namespace splatkit
