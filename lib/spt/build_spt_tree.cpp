#include "spt/build_spt_tree.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <span>
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
    const auto it = std::partition_point(keys.begin() + static_cast<std::ptrdiff_t>(from),
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

// A subtree over a sorted range, built sequentially with local interior numbers.
struct Subtree {
  std::vector<SptDisc> interiors;
  std::vector<uint32_t> interior_parent;  // local numbers; the root's is kNoParent
  uint32_t root = 0;                      // splat number when leaf_root, else local interior
  bool leaf_root = false;
  uint32_t depth = 0;
  SptDisc root_disc;
};

struct Builder {
  const SptInput& in;
  std::vector<Keyed>& keys;
  float color_weight;
  bool has_color;
  std::vector<uint32_t>& parent;  // leaves' parents (local numbers inside a subtree, for now)

  // Builds [b, e) into `t`; returns (node ref, disc) with ref = splat | local interior << 1 tag.
  std::pair<uint64_t, SptDisc> build(Subtree& t, std::size_t b, std::size_t e, uint32_t depth,
                                     std::vector<std::size_t>& cuts) const {
    if (e - b == 1) {
      t.depth = std::max(t.depth, depth);
      const uint32_t s = keys[b].second;
      return {uint64_t{s} << 1, in.leaf(s)};
    }
    split_range(in, keys, b, e, cuts);
    const std::vector<std::size_t> mine = cuts;
    std::vector<SptDisc> discs;
    std::vector<uint64_t> refs;
    discs.reserve(mine.size() - 1);
    refs.reserve(mine.size() - 1);
    for (std::size_t k = 0; k + 1 < mine.size(); ++k) {
      auto [ref, disc] = build(t, mine[k], mine[k + 1], depth + 1, cuts);
      refs.push_back(ref);
      discs.push_back(disc);
    }
    const uint32_t id = static_cast<uint32_t>(t.interiors.size());
    t.interiors.push_back(fit_spt_disc(discs, color_weight, has_color));
    t.interior_parent.push_back(kNoParent);
    for (uint64_t ref : refs) {
      if (ref & 1)
        t.interior_parent[ref >> 1] = id;
      else
        parent[ref >> 1] = id;
    }
    return {uint64_t{id} << 1 | 1, t.interiors.back()};
  }
};

// The top of the tree, above the parallel subtrees.
struct TopNode {
  std::vector<std::pair<bool, uint32_t>> children;  // (is a top node, index), else subtree index
};

}  // namespace

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
  const Builder builder{in, keys, color_weight, !in.colors.empty(), parent};

  // The top: ranges above the grain split sequentially; the rest become subtrees.
  constexpr std::size_t kGrain = 4096;
  std::vector<TopNode> top;
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  std::vector<uint32_t> range_depth;
  std::vector<std::size_t> cuts;
  auto split_top = [&](auto&& self, std::size_t b, std::size_t e, uint32_t depth) -> std::pair<bool, uint32_t> {
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

  std::vector<Subtree> subtrees(ranges.size());
  tbb::parallel_for(std::size_t{0}, ranges.size(), [&](std::size_t k) {
    std::vector<std::size_t> local_cuts;
    Subtree& t = subtrees[k];
    auto [ref, disc] = builder.build(t, ranges[k].first, ranges[k].second, range_depth[k], local_cuts);
    t.root = static_cast<uint32_t>(ref >> 1);
    t.leaf_root = (ref & 1) == 0;
    t.root_disc = disc;
  });

  // Global numbers: the subtrees' interiors in order, then the top nodes in post-order.
  std::vector<uint32_t> offset(subtrees.size() + 1, static_cast<uint32_t>(n));
  for (std::size_t k = 0; k < subtrees.size(); ++k)
    offset[k + 1] = offset[k] + static_cast<uint32_t>(subtrees[k].interiors.size());
  const std::size_t interiors_below = offset.back() - n;
  tree.interiors.resize(interiors_below);
  parent.resize(offset.back(), kNoParent);
  tbb::parallel_for(std::size_t{0}, subtrees.size(), [&](std::size_t k) {
    Subtree& t = subtrees[k];
    for (std::size_t i = ranges[k].first; i < ranges[k].second && !t.leaf_root; ++i)
      parent[keys[i].second] += offset[k];
    for (std::size_t j = 0; j < t.interiors.size(); ++j) {
      tree.interiors[offset[k] - n + j] = t.interiors[j];
      if (t.interior_parent[j] != kNoParent) parent[offset[k] + j] = t.interior_parent[j] + offset[k];
    }
    t.interiors = {};
    t.interior_parent = {};
  });
  for (const Subtree& t : subtrees) tree.depth = std::max(tree.depth, t.depth);
  auto global = [&](std::size_t k) { return subtrees[k].leaf_root ? subtrees[k].root : offset[k] + subtrees[k].root; };

  auto finish_top = [&](auto&& self, uint32_t id) -> std::pair<uint32_t, SptDisc> {
    std::vector<uint32_t> ids;
    std::vector<SptDisc> discs;
    for (auto [is_top, index] : top[id].children) {
      if (is_top) {
        auto [g, d] = self(self, index);
        ids.push_back(g);
        discs.push_back(d);
      } else {
        ids.push_back(global(index));
        discs.push_back(subtrees[index].root_disc);
      }
    }
    const uint32_t g = static_cast<uint32_t>(n + tree.interiors.size());
    tree.interiors.push_back(fit_spt_disc(discs, color_weight, !in.colors.empty()));
    parent.push_back(kNoParent);
    for (uint32_t c : ids) parent[c] = g;
    return {g, tree.interiors.back()};
  };
  if (!top.empty()) finish_top(finish_top, 0);
  return tree;
}

}  // namespace splatkit::spt
