#include "normals/merge_duplicates.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <tuple>

namespace splatkit {

namespace {

struct Key {
  uint32_t x, y, z;
  uint32_t index;
  bool operator<(const Key& o) const {
    return std::tie(x, y, z, index) < std::tie(o.x, o.y, o.z, o.index);
  }
  bool same_position(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};

// Bit pattern with -0 folded onto +0, so that positions equal as floats get equal keys.
uint32_t key_bits(float v) { return std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v); }

template <typename T>
void compact(std::vector<T>& values, const std::vector<uint32_t>& kept) {
  if (values.empty()) return;
  for (std::size_t out = 0; out < kept.size(); ++out) values[out] = values[kept[out]];
  values.resize(kept.size());
  values.shrink_to_fit();
}

}  // namespace

MergeResult merge_duplicates(SplatCloud& cloud, bool want_map) {
  const std::size_t n = cloud.size();
  MergeResult result;
  std::vector<Key> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f& p = cloud.positions[i];
    keys[i] = {key_bits(p.x), key_bits(p.y), key_bits(p.z), static_cast<uint32_t>(i)};
  }
  // Keys are unique (the index is part of them), so the unstable parallel sort is deterministic.
  tbb::parallel_sort(keys.begin(), keys.end());

  // first[i]: the lowest index with point i's position (i itself when i is the first occurrence).
  std::vector<uint32_t> first(n);
  for (std::size_t s = 0; s < n;) {
    std::size_t e = s + 1;
    while (e < n && keys[e].same_position(keys[s])) ++e;
    for (std::size_t t = s; t < e; ++t) first[keys[t].index] = keys[s].index;
    s = e;
  }
  keys = {};

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
    compact(cloud.colors, kept);
    for (ExtraAttribute& extra : cloud.extras) compact(extra.values, kept);
    for (uint32_t& v : cloud.face_indices) v = first[v];
  }
  if (want_map) result.representative = std::move(first);
  return result;
}

}  // namespace splatkit
