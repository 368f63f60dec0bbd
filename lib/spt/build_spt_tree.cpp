#include "spt/build_spt_tree.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <tuple>
#include <utility>

namespace splatkit::spt {

namespace {

using Keyed = std::pair<uint64_t, uint32_t>;  // (Morton code, splat)

// Spreads the low 21 bits of v to every third bit.
uint64_t spread(uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// Morton codes of splats keys[b, e) over the bounding cube of their own centres.
void assign_codes(const SptInput& in, std::span<Keyed> keys) {
  Vec3f lo = in.positions[keys[0].second], hi = lo;
  for (const Keyed& k : keys) {
    const Vec3f& p = in.positions[k.second];
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double extent = std::max({double(hi.x) - lo.x, double(hi.y) - lo.y, double(hi.z) - lo.z});
  const double scale = extent > 0 ? 2097151.0 / extent : 0.0;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 1 << 14), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const Vec3f& p = in.positions[keys[i].second];
      auto q = [&](float v, float l) {
        return static_cast<uint64_t>(std::clamp((double(v) - l) * scale, 0.0, 2097151.0));
      };
      keys[i].first = spread(q(p.x, lo.x)) << 2 | spread(q(p.y, lo.y)) << 1 | spread(q(p.z, lo.z));
    }
  });
}

std::vector<Keyed> sorted_by_morton(const SptInput& in) {
  std::vector<Keyed> keys(in.size());
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i].second = static_cast<uint32_t>(i);
  assign_codes(in, keys);
  if (!std::is_sorted(keys.begin(), keys.end()))  // the caller may have sorted the splats already
    tbb::parallel_sort(keys.begin(), keys.end());
  return keys;
}

// The child ranges of the sorted range [b, e) (size >= 2), appended to `cuts` as boundaries
// b = cuts[0] < cuts[1] < ... < cuts.back() = e: at the first octree digit where the codes differ,
// or one splat each when every code is equal. A range of more than 8 splats with one code (a
// cluster far smaller than the cube's cells, beside a far outlier) gets codes over its own
// bounding cube first, sorted again in place; only coincident centres stay one code.
void split_range(const SptInput& in, std::vector<Keyed>& keys, std::size_t b, std::size_t e,
                 std::vector<std::size_t>& cuts) {
  cuts.clear();
  uint64_t x = keys[b].first ^ keys[e - 1].first;
  if (x == 0 && e - b > 8) {
    const std::span<Keyed> range(keys.data() + b, e - b);
    assign_codes(in, range);
    std::sort(range.begin(), range.end());
    x = keys[b].first ^ keys[e - 1].first;
  }
  if (x == 0) {
    for (std::size_t i = b; i <= e; ++i) cuts.push_back(i);
    return;
  }
  const int shift = (63 - std::countl_zero(x)) / 3 * 3;
  cuts.push_back(b);
  std::size_t from = b;
  for (uint64_t digit = ((keys[b].first >> shift) & 7) + 1; digit < 8; ++digit) {
    const auto it =
        std::partition_point(keys.begin() + static_cast<std::ptrdiff_t>(from),
                             keys.begin() + static_cast<std::ptrdiff_t>(e),
                             [&](const Keyed& k) { return ((k.first >> shift) & 7) < digit; });
    const std::size_t at = static_cast<std::size_t>(it - keys.begin());
    if (at > from && at < e) {
      cuts.push_back(at);
      from = at;
    }
  }
  cuts.push_back(e);
}

// A subtree over a sorted range, built sequentially; its interiors take the numbers from `next`
// on, in post-order (counted beforehand, so every subtree writes straight into the tree).
struct Subtree {
  uint32_t next = 0;
  uint32_t depth = 0;
};

struct Builder {
  const SptInput& in;
  std::vector<Keyed>& keys;
  float color_weight;
  bool has_color;
  SptTree& tree;

  // Interior nodes over [b, e), splitting exactly as build will: a cluster that split_range
  // re-codes is put back as it was afterwards, so that build re-codes it the same way.
  uint32_t count(std::size_t b, std::size_t e, std::vector<std::size_t>& cuts) const {
    if (e - b == 1) return 0;
    std::vector<Keyed> saved;
    if (e - b > 8 && keys[b].first == keys[e - 1].first)
      saved.assign(keys.begin() + static_cast<std::ptrdiff_t>(b),
                   keys.begin() + static_cast<std::ptrdiff_t>(e));
    split_range(in, keys, b, e, cuts);
    const std::vector<std::size_t> mine = cuts;
    uint32_t sum = 1;
    for (std::size_t k = 0; k + 1 < mine.size(); ++k) sum += count(mine[k], mine[k + 1], cuts);
    if (!saved.empty())
      std::copy(saved.begin(), saved.end(), keys.begin() + static_cast<std::ptrdiff_t>(b));
    return sum;
  }

  // Builds [b, e) into the tree; returns (node number, disc).
  std::pair<uint32_t, SptDisc> build(Subtree& t, std::size_t b, std::size_t e, uint32_t depth,
                                     std::vector<std::size_t>& cuts) const {
    if (e - b == 1) {
      t.depth = std::max(t.depth, depth);
      const uint32_t s = keys[b].second;
      return {s, in.leaf(s)};
    }
    if (e - b <= 32) prefetch(b, e);
    split_range(in, keys, b, e, cuts);
    const std::size_t kids = cuts.size() - 1;
    if (kids <= 8) {  // the usual case, without allocating
      std::array<std::size_t, 9> mine;
      std::copy(cuts.begin(), cuts.end(), mine.begin());
      std::array<SptDisc, 8> discs;
      std::array<uint32_t, 8> ids;
      for (std::size_t k = 0; k < kids; ++k)
        std::tie(ids[k], discs[k]) = build(t, mine[k], mine[k + 1], depth + 1, cuts);
      return attach(t, std::span(ids.data(), kids), std::span(discs.data(), kids));
    }
    const std::vector<std::size_t> mine = cuts;
    std::vector<SptDisc> discs(kids);
    std::vector<uint32_t> ids(kids);
    for (std::size_t k = 0; k < kids; ++k)
      std::tie(ids[k], discs[k]) = build(t, mine[k], mine[k + 1], depth + 1, cuts);
    return attach(t, ids, discs);
  }

  // The splats of a small range are scattered in memory (input order): ask for all of them at
  // once instead of missing the cache one leaf at a time.
  void prefetch(std::size_t b, std::size_t e) const {
    for (std::size_t i = b; i < e; ++i) {
      const uint32_t s = keys[i].second;
      __builtin_prefetch(&in.positions[s]);
      __builtin_prefetch(&in.normals[s]);
      __builtin_prefetch(&in.radii[s]);
      if (has_color) __builtin_prefetch(&in.colors[s]);
    }
  }

  // The next interior node of `t` over children `ids` with discs `discs`.
  std::pair<uint32_t, SptDisc> attach(Subtree& t, std::span<const uint32_t> ids,
                                      std::span<const SptDisc> discs) const {
    const uint32_t id = t.next++;
    SptDisc& d = tree.interiors[id - in.size()];
    d = fit_spt_disc(discs, color_weight, has_color);
    for (uint32_t c : ids) tree.parent[c] = id;
    return {id, d};
  }
};

// The top of the tree, above the parallel subtrees.
struct TopNode {
  std::vector<std::pair<bool, uint32_t>> children;  // (is a top node, index), else subtree index
};

}  // namespace

std::vector<uint32_t> morton_order(std::span<const Vec3f> positions) {
  const SptInput in{positions, {}, {}, {}, 8};
  const std::vector<Keyed> keys = sorted_by_morton(in);
  std::vector<uint32_t> order(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

SptDisc SptInput::leaf(std::size_t i) const {
  SptDisc d;
  d.centre = positions[i];
  d.normal = normals[i];
  d.radius = radii[i];
  if (!colors.empty()) {
    const int shift = color_bits > 8 ? 8 : 0;
    d.color = {static_cast<float>(colors[i][0] >> shift), static_cast<float>(colors[i][1] >> shift),
               static_cast<float>(colors[i][2] >> shift)};
  }
  return d;
}

SptTree build_spt_tree(const SptInput& in, float color_weight) {
  const std::size_t n = in.size();
  SptTree tree;
  std::vector<uint32_t>& parent = tree.parent;
  parent.assign(n, kNoParent);
  std::vector<Keyed> keys = sorted_by_morton(in);
  const Builder builder{in, keys, color_weight, !in.colors.empty(), tree};

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
    split_range(in, keys, b, e, cuts);
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

  // Numbers: the subtrees' interiors in order, then the top nodes in post-order.
  std::vector<uint32_t> offset(ranges.size() + 1, static_cast<uint32_t>(n));
  tbb::parallel_for(std::size_t{0}, ranges.size(), [&](std::size_t k) {
    std::vector<std::size_t> local_cuts;
    offset[k + 1] = builder.count(ranges[k].first, ranges[k].second, local_cuts);
  });
  for (std::size_t k = 0; k < ranges.size(); ++k) offset[k + 1] += offset[k];
  tree.interiors.resize(offset.back() - n + top.size());
  parent.resize(offset.back() + top.size(), kNoParent);
  std::vector<Subtree> subtrees(ranges.size());
  std::vector<std::pair<uint32_t, SptDisc>> roots(ranges.size());
  tbb::parallel_for(std::size_t{0}, ranges.size(), [&](std::size_t k) {
    std::vector<std::size_t> local_cuts;
    subtrees[k].next = offset[k];
    roots[k] =
        builder.build(subtrees[k], ranges[k].first, ranges[k].second, range_depth[k], local_cuts);
  });
  for (const Subtree& t : subtrees) tree.depth = std::max(tree.depth, t.depth);
  uint32_t next_top = offset.back();
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
    const uint32_t g = next_top++;
    tree.interiors[g - n] = fit_spt_disc(discs, color_weight, !in.colors.empty());
    for (uint32_t c : ids) parent[c] = g;
    return {g, tree.interiors[g - n]};
  };
  if (!top.empty()) finish_top(finish_top, 0);
  return tree;
}

}  // namespace splatkit::spt
