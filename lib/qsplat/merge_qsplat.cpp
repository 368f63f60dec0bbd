#include "qsplat/merge_qsplat.h"

#include <limits>
#include <vector>

#include "formats/describe_qsplat.h"
#include "formats/rgb565.h"
#include "qsplat/fit_qsplat_nodes.h"
#include "splatkit/common_origin.h"
#include "splatkit/error.h"

namespace splatkit::qsplat {

namespace {

constexpr uint32_t kUpper = std::numeric_limits<uint32_t>::max();

// A node of the merged tree: node `node` of tile `tile`, or of the upper tree (tile kUpper).
struct Ref {
  uint32_t tile, node;
};

void check_tiles(std::span<const QSplatModel> tiles, std::span<const std::string> names) {
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const QSplatModel& m = tiles[t];
    if (m.tree_fragments != 1)
      throw_bad_input(names[t], std::to_string(m.tree_fragments) +
                                    " tree fragments; a tile's file holds one (build-qsplat's)");
    if (m.has_color != tiles[0].has_color)
      throw_bad_input(names[t], std::string("colour ") + (m.has_color ? "present" : "absent") +
                                    " differs from " + names[0] +
                                    "'s (the tiles must all have "
                                    "colours or none: build-qsplat --no-color on all or none)");
  }
}

}  // namespace

MergedQSplatTree merge_qsplat_tree(std::span<const QSplatModel> tiles,
                                   std::span<const std::string> names) {
  check_tiles(tiles, names);
  const bool color = tiles[0].has_color;
  MergedQSplatTree out;
  std::vector<std::array<double, 3>> origins;
  for (const QSplatModel& m : tiles) origins.push_back(qsplat_origin(m));
  out.origin = common_origin(origins);
  // Tile t's centre i in the common frame.
  auto centre = [&](std::size_t t, uint32_t i) {
    const Vec3f& p = tiles[t].centres[i];
    if (origins[t] == out.origin) return p;
    Vec3f q;
    for (int a = 0; a < 3; ++a)
      q[a] = static_cast<float>(origins[t][a] - out.origin[a] + double(p[a]));
    return q;
  };
  // The upper tree's shape over the tiles' roots (their header spheres), as over splats.
  QSplatTree up;
  if (tiles.size() > 1) {
    QSplatLeaves roots;
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      roots.positions.push_back(centre(t, tiles[t].roots[0]));
      roots.normals.push_back({0, 0, 1});
      roots.radii.push_back(tiles[t].radii[tiles[t].roots[0]]);
    }
    up = build_qsplat_tree(roots, false, false);
  }
  // An upper leaf is its tile's root; a node with one child is that child.
  auto resolve = [&](Ref r) {
    if (r.tile == kUpper && up.child_count[r.node] == 0) {
      const uint32_t t = up.leaf[r.node];
      r = {t, tiles[t].roots[0]};
    }
    while (r.tile != kUpper && tiles[r.tile].child_count[r.node] == 1)
      r.node = tiles[r.tile].first_child[r.node];
    return r;
  };
  auto count_of = [&](Ref r) -> uint32_t {
    return r.tile == kUpper ? up.child_count[r.node] : tiles[r.tile].child_count[r.node];
  };
  auto child = [&](Ref r, uint32_t k) {
    const uint32_t f =
        r.tile == kUpper ? up.first_child[r.node] : tiles[r.tile].first_child[r.node];
    return resolve({r.tile, f + k});
  };

  // Breadth first, level by level, each node's children after the earlier nodes' children.
  QSplatTree& t = out.tree;
  QSplatLeaves leaves;
  std::vector<uint32_t> leaf_of;
  std::vector<Ref> level{resolve(tiles.size() > 1 ? Ref{kUpper, 0} : Ref{0, tiles[0].roots[0]})};
  t.level_begin = {0};
  uint32_t begin = 0;
  while (!level.empty()) {
    const auto end = begin + static_cast<uint32_t>(level.size());
    t.level_begin.push_back(end);
    std::vector<Ref> next;
    uint32_t at = end;
    for (const Ref& r : level) {
      const uint32_t c = count_of(r);
      t.first_child.push_back(c > 0 ? at : 0);
      t.child_count.push_back(static_cast<uint8_t>(c));
      if (r.tile == kUpper) ++out.upper_nodes;
      if (c == 0) {
        const QSplatModel& m = tiles[r.tile];
        leaf_of.push_back(static_cast<uint32_t>(leaves.size()));
        leaves.positions.push_back(centre(r.tile, r.node));
        leaves.radii.push_back(m.radii[r.node]);
        leaves.normals.push_back(decode_normal(m.normal_codes[r.node]));
        if (color) leaves.colors.push_back(decode_rgb565(m.colors[r.node]));
        continue;
      }
      leaf_of.push_back(kNoLeaf);
      for (uint32_t k = 0; k < c; ++k) next.push_back(child(r, k));
      at += c;
    }
    begin = end;
    level = std::move(next);
  }
  out.leaves = leaves.size();
  t.leaf.allocate(leaf_of.size());
  for (std::size_t i = 0; i < leaf_of.size(); ++i) t.leaf[i] = leaf_of[i];
  fit_qsplat_nodes(t, leaves, /*centroid_rule=*/false, /*measure=*/false);
  return out;
}

}  // namespace splatkit::qsplat
