#include "spt/build_spt_tree.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

#include "formats/spt_codes.h"
#include "splatkit/morton_order.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::spt {

namespace {

// Levels: a run ordered again over its own cube (a cluster) ranks below every level outside it.
constexpr int kMaxClusterDepth = 10;
uint8_t level_of(uint64_t x, int depth) {
  if (x == 0 || depth > kMaxClusterDepth) return 0;
  return static_cast<uint8_t>(1 + (63 - std::countl_zero(x)) / 3 + 22 * (kMaxClusterDepth - depth));
}

// v[b + i] = old v[b + from[i]] for the range [b, b + from.size()).
template <class T>
void permute_range(std::vector<T>& v, std::size_t b, const std::vector<uint32_t>& from) {
  if (v.empty()) return;
  std::vector<T> tmp(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) tmp[i] = v[b + from[i]];
  std::copy(tmp.begin(), tmp.end(), v.begin() + static_cast<std::ptrdiff_t>(b));
}

// A stable counting sort of elements into 256 buckets (one byte each), in fixed blocks in
// parallel: every block writes after the earlier blocks' share of each bucket, so the places are
// the serial ones for any thread count, and the same scatter can be repeated for other arrays.
class BucketPass {
 public:
  static constexpr std::size_t kBuckets = 256, kBlock = std::size_t{1} << 16;

  explicit BucketPass(std::vector<uint8_t> buckets)
      : buckets_(std::move(buckets)),
        blocks_((buckets_.size() + kBlock - 1) / kBlock),
        first_(blocks_ * kBuckets) {
    tbb::parallel_for(std::size_t{0}, blocks_, [&](std::size_t blk) {
      std::size_t* c = first_.data() + blk * kBuckets;
      for (std::size_t i = blk * kBlock, e = std::min(buckets_.size(), i + kBlock); i < e; ++i)
        ++c[buckets_[i]];
    });
    std::size_t sum = 0;  // buckets in order, blocks in order within a bucket
    for (std::size_t d = 0; d < kBuckets; ++d) {
      start_[d] = sum;
      for (std::size_t blk = 0; blk < blocks_; ++blk)
        sum += std::exchange(first_[blk * kBuckets + d], sum);
    }
    start_[kBuckets] = sum;
  }
  // The places of bucket d: [start(d), start(d + 1)).
  std::size_t start(std::size_t d) const { return start_[d]; }
  // f(i, place of element i) for every element, each block's in order on one task.
  template <class F>
  void scatter(F&& f) const {
    tbb::parallel_for(std::size_t{0}, blocks_, [&](std::size_t blk) {
      std::array<std::size_t, kBuckets> next;
      std::copy_n(first_.begin() + blk * kBuckets, kBuckets, next.begin());
      for (std::size_t i = blk * kBlock, e = std::min(buckets_.size(), i + kBlock); i < e; ++i)
        f(i, next[buckets_[i]]++);
    });
  }

 private:
  std::vector<uint8_t> buckets_;
  std::size_t blocks_;
  std::vector<std::size_t> first_;  // per block and bucket: its first place
  std::array<std::size_t, kBuckets + 1> start_;
};

// One array's elements in a byte buffer (uninitialised memory shared by the arrays in turn:
// memcpy makes the objects there).
template <class T>
void put_element(unsigned char* buffer, std::size_t i, const T& v) {
  std::memcpy(buffer + i * sizeof(T), &v, sizeof(T));
}
template <class T>
T element(const unsigned char* buffer, std::size_t i) {
  T v;
  std::memcpy(&v, buffer + i * sizeof(T), sizeof(T));
  return v;
}

// A code and the place of its splat.
struct Coded {
  uint64_t code;
  uint32_t place;
};

// Sorts v[0, m) by the codes' bits [0, high), keeping the order of equal codes (least
// significant digit first, 11 bits a pass, through `scratch`; a pass where every code has the
// same digit is skipped). For the splats of one bucket, mostly in cache.
void radix_sort_codes(Coded* v, Coded* scratch, std::size_t m, int high) {
  constexpr int kBits = 11;
  std::vector<std::size_t> at(std::size_t{1} << kBits);
  for (int shift = 0; shift < high; shift += kBits) {
    const uint64_t mask = (uint64_t{1} << std::min(kBits, high - shift)) - 1;
    std::fill(at.begin(), at.end(), std::size_t{0});
    for (std::size_t i = 0; i < m; ++i) ++at[(v[i].code >> shift) & mask];
    if (std::find(at.begin(), at.end(), m) != at.end()) continue;
    std::size_t sum = 0;
    for (std::size_t& a : at) sum += std::exchange(a, sum);
    for (std::size_t i = 0; i < m; ++i) scratch[at[(v[i].code >> shift) & mask]++] = v[i];
    std::copy(scratch, scratch + m, v);
  }
}

struct Sorter {
  SptSplats& s;
  std::vector<uint8_t>& levels;
  std::vector<uint32_t>* old_index;

  // Orders the cluster [b, e) by codes over its own bounding cube (ties in place), sets its
  // levels for `depth`, and does the same for the clusters inside it.
  void recode(std::size_t b, std::size_t e, int depth) {
    if (depth > kMaxClusterDepth) return;
    const Bounds box = compute_bounds(std::span<const Vec3f>(s.positions).subspan(b, e - b));
    const MortonFrame frame(box.min, box.max);
    std::vector<std::pair<uint64_t, uint32_t>> keys(e - b);
    for (std::size_t i = b; i < e; ++i)
      keys[i - b] = {frame.code(s.positions[i]), static_cast<uint32_t>(i - b)};
    std::sort(keys.begin(), keys.end());
    if (keys.front().first == keys.back().first) return;  // coincident: one node
    std::vector<uint32_t> from(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) from[i] = keys[i].second;
    permute_range(s.positions, b, from);
    permute_range(s.normals, b, from);
    permute_range(s.radii, b, from);
    permute_range(s.colors, b, from);
    if (old_index) permute_range(*old_index, b, from);
    for (std::size_t i = b; i + 1 < e; ++i)
      levels[i] = level_of(keys[i - b].first ^ keys[i + 1 - b].first, depth);
    clusters(b, e, depth + 1);
  }

  // Every run of more than 8 equal codes in [b, e) ordered again.
  void clusters(std::size_t b, std::size_t e, int depth) {
    for (std::size_t i = b; i + 1 < e;) {
      if (levels[i] != 0) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j + 1 < e && levels[j] == 0) ++j;  // splats i..j have one code
      if (j - i + 1 > 8) recode(i, j + 1, depth);
      i = j + 1;
    }
  }
};

// A subtree over a sorted range, built sequentially: slot s is stored at recs[s] (a scratch
// buffer, copied into the tree afterwards, or the tree's own records for the top).
struct Subtree {
  SptRecord* recs = nullptr;
  SptFullRecord* fulls = nullptr;
  uint32_t next = 0;  // the next slot
  uint32_t depth = 0;
  float error_lo = INFINITY, error_hi = 0, radius_lo = INFINITY, radius_hi = 0;
};

struct Builder {
  const SptSplats& in;
  const uint8_t* levels;
  SptTree& tree;
  float color_weight;
  bool has_color, full;

  // The child ranges of [b, e) (size >= 2) as boundaries b = cuts[0] < ... < cuts.back() = e:
  // at the highest level in the range, or one splat each when every code is equal.
  void split(std::size_t b, std::size_t e, std::vector<std::size_t>& cuts) const {
    cuts.clear();
    const uint8_t top = *std::max_element(levels + b, levels + e - 1);
    cuts.push_back(b);
    for (std::size_t i = b; i + 1 < e; ++i)
      if (levels[i] == top) cuts.push_back(i + 1);
    cuts.push_back(e);
  }

  // Builds [b, e) into the tree; returns its node number and constructs its disc at `disc`
  // (storage that may hold no object yet: a node's child discs are not zeroed first).
  uint32_t build(Subtree& t, std::size_t b, std::size_t e, uint32_t depth,
                 std::vector<std::size_t>& cuts, SptDisc* disc) const {
    if (e - b == 1) {
      t.depth = std::max(t.depth, depth);
      std::construct_at(disc, in.leaf(b));
      return static_cast<uint32_t>(b);
    }
    split(b, e, cuts);
    const std::size_t kids = cuts.size() - 1;
    if (kids <= 8) {  // the usual case, without allocating
      std::array<std::size_t, 9> mine;
      std::copy(cuts.begin(), cuts.end(), mine.begin());
      alignas(SptDisc) unsigned char storage[8 * sizeof(SptDisc)];
      SptDisc* const discs = reinterpret_cast<SptDisc*>(storage);
      std::array<uint32_t, 8> ids;
      for (std::size_t k = 0; k < kids; ++k)
        ids[k] = build(t, mine[k], mine[k + 1], depth + 1, cuts, discs + k);
      return attach(t, std::span(ids.data(), kids),
                    std::span<const SptDisc>(std::launder(discs), kids), disc);
    }
    const std::vector<std::size_t> mine = cuts;
    std::vector<SptDisc> discs(kids);
    std::vector<uint32_t> ids(kids);
    for (std::size_t k = 0; k < kids; ++k)
      ids[k] = build(t, mine[k], mine[k + 1], depth + 1, cuts, &discs[k]);
    return attach(t, ids, discs, disc);
  }

  // The next interior node of `t` over children `ids` with discs `discs`: returns its number and
  // constructs its disc at `disc`.
  uint32_t attach(Subtree& t, std::span<const uint32_t> ids, std::span<const SptDisc> discs,
                  SptDisc* disc) const {
    const uint32_t slot = t.next++;
    const SptDisc& d = *std::construct_at(disc, fit_spt_disc(discs, color_weight, has_color));
    store(t, slot, d);
    if (d.error > 0) {
      t.error_lo = std::min(t.error_lo, d.error);
      t.error_hi = std::max(t.error_hi, d.error);
    }
    if (d.radius > 0) {
      t.radius_lo = std::min(t.radius_lo, d.radius);
      t.radius_hi = std::max(t.radius_hi, d.radius);
    }
    const uint32_t id = static_cast<uint32_t>(in.size() + slot);
    for (uint32_t c : ids) {
      if (c < in.size())
        tree.leaf_parent[c] = id;
      else
        t.recs[c - in.size()].parent = id;
    }
    return id;
  }

  void store(Subtree& t, uint32_t slot, const SptDisc& d) const {
    std::array<uint8_t, 3> rgb{0, 0, 0};
    if (has_color) {
      auto q = [](float v) {
        return static_cast<uint8_t>(std::clamp(std::floor(v + 0.5f), 0.0f, 255.0f));
      };
      rgb = {q(d.color.x), q(d.color.y), q(d.color.z)};
    }
    SptRecord& r = t.recs[slot];
    r.q = {encode_position(d.centre.x, tree.box_min.x, tree.step.x),
           encode_position(d.centre.y, tree.box_min.y, tree.step.y),
           encode_position(d.centre.z, tree.box_min.z, tree.step.z)};
    r.normal = encode_normal(d.normal);
    r.rgb565 = has_color ? encode_rgb565(rgb) : 0;
    r.r_min = 0;
    r.radius = d.radius;
    r.error = d.error;
    r.parent = kNoParent;
    if (full) t.fulls[slot] = {d.centre, d.normal, rgb};
  }
};

// The top of the tree, above the parallel subtrees.
struct TopNode {
  std::vector<std::pair<bool, uint32_t>> children;  // (is a top node, index), else subtree index
};

}  // namespace

SptDisc SptSplats::leaf(std::size_t i) const {
  SptDisc d;
  d.centre = positions[i];
  d.normal = normals[i];
  d.radius = radii[i];
  if (!colors.empty())
    d.color = {static_cast<float>(colors[i][0]), static_cast<float>(colors[i][1]),
               static_cast<float>(colors[i][2])};
  return d;
}

SptSplats take_spt_splats(SplatCloud& cloud) {
  SptSplats s;
  s.positions = std::move(cloud.positions);
  s.normals = std::move(cloud.normals);
  s.radii = std::move(cloud.radii);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.normals.size(), 1 << 14),
                    [&](const auto& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        s.normals[i] = normalized(s.normals[i]);
                    });
  if (!cloud.colors.empty()) {
    const int shift = cloud.color_bits > 8 ? 8 : 0;
    s.colors.resize(cloud.colors.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.colors.size(), 1 << 14),
                      [&](const auto& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i)
                          for (int k = 0; k < 3; ++k)
                            s.colors[i][k] = static_cast<uint8_t>(cloud.colors[i][k] >> shift);
                      });
    std::vector<std::array<uint16_t, 3>>().swap(cloud.colors);
  }
  return s;
}

SptOrder sort_spt_splats(SptSplats& s, std::vector<uint32_t>* old_index, const Bounds* frame_box) {
  const std::size_t n = s.size();
  SptOrder order;
  const Bounds box = frame_box ? *frame_box : compute_bounds(s.positions);
  order.lo = box.min;
  order.hi = box.max;
  const MortonFrame frame(box.min, box.max);
  // Sorted by code, ties in input order, in two steps so that the splats are never read at
  // random over whole arrays: a stable pass by the codes' top 8 bits moves each array into 256
  // buckets (read in order, written to 256 places), then each bucket's codes are made again from
  // its positions and sorted (in cache), and each array is gathered back within its bucket. Within
  // a bucket the places keep the input's order. One buffer holds each array's buckets in turn.
  constexpr int kCodeBits = 63, kTopBits = 8;
  std::vector<uint8_t> top;
  sized_in_parallel(top, n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i)
      top[i] = static_cast<uint8_t>(frame.code(s.positions[i]) >> (kCodeBits - kTopBits));
  });
  const BucketPass pass(std::move(top));
  const std::unique_ptr<unsigned char[]> buffer(new unsigned char[n * sizeof(Vec3f)]);
  auto to_buckets = [&](const auto& v) {
    pass.scatter([&](std::size_t i, std::size_t at) { put_element(buffer.get(), at, v[i]); });
  };
  to_buckets(s.positions);
  // from[d]: the place of the splat that goes to d; levels within buckets here, between them below.
  std::vector<uint32_t> from;
  sized_in_parallel(from, n);
  sized_in_parallel(order.levels, n - 1);
  std::array<uint64_t, BucketPass::kBuckets> first_code{}, last_code{};
  // Per thread, the largest bucket's codes so far and as much scratch (fresh pages cost more
  // than sorting in them).
  tbb::enumerable_thread_specific<std::pair<std::vector<Coded>, std::vector<Coded>>> work;
  tbb::parallel_for(std::size_t{0}, BucketPass::kBuckets, [&](std::size_t d) {
    const std::size_t b = pass.start(d), m = pass.start(d + 1) - b;
    if (m == 0) return;
    auto& [coded, scratch] = work.local();
    if (coded.size() < m) {
      coded.resize(m);
      scratch.resize(m);
    }
    for (std::size_t j = 0; j < m; ++j)
      coded[j] = {frame.code(element<Vec3f>(buffer.get(), b + j)), static_cast<uint32_t>(b + j)};
    radix_sort_codes(coded.data(), scratch.data(), m, kCodeBits - kTopBits);
    for (std::size_t j = 0; j < m; ++j) {
      from[b + j] = coded[j].place;
      if (j + 1 < m) order.levels[b + j] = level_of(coded[j].code ^ coded[j + 1].code, 0);
    }
    first_code[d] = coded[0].code;
    last_code[d] = coded[m - 1].code;
  });
  for (std::size_t d = 0, previous = 0; d < BucketPass::kBuckets; ++d) {
    if (pass.start(d + 1) == pass.start(d)) continue;
    if (pass.start(d) > 0)
      order.levels[pass.start(d) - 1] = level_of(last_code[previous] ^ first_code[d], 0);
    previous = d;
  }
  if (old_index) {
    std::vector<uint32_t> input_index(n);  // per place
    pass.scatter(
        [&](std::size_t i, std::size_t at) { input_index[at] = static_cast<uint32_t>(i); });
    old_index->resize(n);
    for (std::size_t i = 0; i < n; ++i) (*old_index)[i] = input_index[from[i]];
  }
  auto gather_back = [&](auto& v) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t d = r.begin(); d < r.end(); ++d) v[d] = element<T>(buffer.get(), from[d]);
    });
  };
  gather_back(s.positions);
  auto reorder = [&](auto& v) {
    if (v.empty()) return;
    to_buckets(v);
    gather_back(v);
  };
  reorder(s.normals);
  reorder(s.radii);
  reorder(s.colors);
  Sorter{s, order.levels, old_index}.clusters(0, n, 1);
  return order;
}

SptTree build_spt_tree(const SptSplats& in, const SptOrder& order, const SptTreeOptions& o) {
  const std::size_t n = in.size();
  SptTree tree;
  tree.leaves = n;
  tree.leaf_parent.reserve(n);  // its pages mapped in parallel, then filled once
  map_pages_in_parallel(tree.leaf_parent.data(), tree.leaf_parent.data() + n);
  tree.leaf_parent.assign(n, kNoParent);
  tree.box_min = order.lo;
  tree.step = {(order.hi.x - order.lo.x) / 65535.0f, (order.hi.y - order.lo.y) / 65535.0f,
               (order.hi.z - order.lo.z) / 65535.0f};
  const Builder builder{in, order.levels.data(), tree, o.color_weight, !in.colors.empty(), o.full};

  // The top: ranges above the grain split sequentially; the rest become subtrees.
  constexpr std::size_t kGrain = 4096;
  std::vector<TopNode> top;
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  std::vector<uint32_t> range_depth;
  std::vector<std::size_t> cuts;
  auto split_top = [&](auto&& self, std::size_t b, std::size_t e,
                       uint32_t depth) -> std::pair<bool, uint32_t> {
    if (e - b <= kGrain) {
      ranges.push_back({b, e});
      range_depth.push_back(depth);
      return {false, static_cast<uint32_t>(ranges.size() - 1)};
    }
    builder.split(b, e, cuts);
    const std::vector<std::size_t> mine = cuts;
    const uint32_t id = static_cast<uint32_t>(top.size());
    top.emplace_back();
    for (std::size_t k = 0; k + 1 < mine.size(); ++k) {
      auto child = self(self, mine[k], mine[k + 1], depth + 1);
      top[id].children.push_back(child);
    }
    return {true, id};
  };
  split_top(split_top, 0, n, 0);

  // Subtrees in batches: built in parallel into scratch buffers, then copied into the tree in
  // order (so the records take exactly their memory) with their numbers shifted.
  tree.records.allocate(n);
  if (o.full) tree.full_records.allocate(n);
  std::vector<std::pair<uint32_t, SptDisc>> roots(ranges.size());
  constexpr std::size_t kBatch = 64;
  std::vector<std::vector<SptRecord>> scratch(kBatch);
  std::vector<std::vector<SptFullRecord>> full_scratch(o.full ? kBatch : 0);
  std::vector<Subtree> batch(kBatch);
  std::vector<uint32_t> base(kBatch);
  Subtree sum;
  for (std::size_t b0 = 0; b0 < ranges.size(); b0 += kBatch) {
    const std::size_t count = std::min(kBatch, ranges.size() - b0);
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t j) {
      const std::size_t k = b0 + j;
      scratch[j].resize(ranges[k].second - ranges[k].first);
      if (o.full) full_scratch[j].resize(scratch[j].size());
      batch[j] = {};
      batch[j].recs = scratch[j].data();
      batch[j].fulls = o.full ? full_scratch[j].data() : nullptr;
      std::vector<std::size_t> local_cuts;
      roots[k].first = builder.build(batch[j], ranges[k].first, ranges[k].second, range_depth[k],
                                     local_cuts, &roots[k].second);
    });
    for (std::size_t j = 0; j < count; ++j) {
      base[j] = sum.next;
      sum.next += batch[j].next;
    }
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t j) {
      const std::size_t k = b0 + j;
      const uint32_t shift = base[j];
      for (uint32_t s = 0; s < batch[j].next; ++s) {
        SptRecord r = scratch[j][s];
        if (r.parent != kNoParent) r.parent += shift;
        tree.records[shift + s] = r;
        if (o.full) tree.full_records[shift + s] = full_scratch[j][s];
      }
      if (batch[j].next > 0) {
        for (std::size_t i = ranges[k].first; i < ranges[k].second; ++i)
          tree.leaf_parent[i] += shift;
        roots[k].first += shift;
      }
    });
    for (std::size_t j = 0; j < count; ++j) {
      const Subtree& t = batch[j];
      sum.depth = std::max(sum.depth, t.depth);
      sum.error_lo = std::min(sum.error_lo, t.error_lo);
      sum.error_hi = std::max(sum.error_hi, t.error_hi);
      sum.radius_lo = std::min(sum.radius_lo, t.radius_lo);
      sum.radius_hi = std::max(sum.radius_hi, t.radius_hi);
    }
  }
  std::vector<std::vector<SptRecord>>().swap(scratch);
  std::vector<std::vector<SptFullRecord>>().swap(full_scratch);
  tree.interiors = sum.next;
  sum.recs = tree.records.get();
  sum.fulls = o.full ? tree.full_records.get() : nullptr;
  auto finish_top = [&](auto&& self, uint32_t id) -> std::pair<uint32_t, SptDisc> {
    std::vector<uint32_t> ids;
    std::vector<SptDisc> discs;
    for (auto [is_top, index] : top[id].children) {
      if (is_top) {
        auto [g, d] = self(self, index);
        ids.push_back(g);
        discs.push_back(d);
      } else {
        ids.push_back(roots[index].first);
        discs.push_back(roots[index].second);
      }
    }
    std::pair<uint32_t, SptDisc> node;
    node.first = builder.attach(sum, ids, discs, &node.second);
    return node;
  };
  if (!top.empty()) finish_top(finish_top, 0);
  tree.interiors = sum.next;
  tree.depth = sum.depth;
  tree.error_lo = sum.error_lo;
  tree.error_hi = sum.error_hi;
  // The leaves' radii.
  using MinMax = std::pair<float, float>;
  const MinMax leaf_radii = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 1 << 16), MinMax{INFINITY, 0.0f},
      [&](const auto& r, MinMax m) {
        for (std::size_t i = r.begin(); i < r.end(); ++i)
          if (in.radii[i] > 0)
            m = {std::min(m.first, in.radii[i]), std::max(m.second, in.radii[i])};
        return m;
      },
      [](MinMax a, const MinMax& b) {
        return MinMax{std::min(a.first, b.first), std::max(a.second, b.second)};
      });
  tree.radius_lo = std::min(sum.radius_lo, leaf_radii.first);
  tree.radius_hi = std::max(sum.radius_hi, leaf_radii.second);
  return tree;
}

}  // namespace splatkit::spt
