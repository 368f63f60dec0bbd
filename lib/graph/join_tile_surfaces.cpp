#include "graph/join_tile_surfaces.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "graph/lowest_root_union_find.h"

namespace splatkit::graph {

void TileSurfaceJoin::add_tile(const std::array<double, 3>& origin,
                               std::span<const Vec3f> positions, std::span<const uint32_t> own,
                               std::span<const uint32_t> surface, uint32_t count) {
  if (surface.size() != positions.size())
    throw std::invalid_argument("join_tile_surfaces: surface ids and positions differ in size");
  const auto base = static_cast<uint32_t>(tile_of_label_.size());
  if (uint64_t{base} + count >= kNoSurface)
    throw std::invalid_argument("join_tile_surfaces: too many surfaces");
  tile_of_label_.insert(tile_of_label_.end(), count, tiles_++);
  const auto point = [&](uint32_t i) {
    const Vec3f& p = positions[i];
    const uint32_t s = surface[i];
    if (s != kNoSurface && s >= count)
      throw std::invalid_argument("join_tile_surfaces: a surface id beyond the count");
    return Point{{origin[0] + p.x, origin[1] + p.y, origin[2] + p.z},
                 s == kNoSurface ? kNoSurface : base + s};
  };
  std::size_t next = 0;  // walks `own` alongside the points
  for (uint32_t i = 0; i < positions.size(); ++i) {
    if (next < own.size() && own[next] == i) {
      own_.push_back(point(i));
      ++next;
    } else if (surface[i] != kNoSurface) {
      halo_.push_back(point(i));
    }
  }
  if (next != own.size())
    throw std::invalid_argument("join_tile_surfaces: own indices not ascending or out of range");
}

Segmentation TileSurfaceJoin::finish(TileJoinInfo* info) {
  const auto labels = static_cast<uint32_t>(tile_of_label_.size());
  // The own points by position, for the halo points to find their owners.
  std::vector<uint32_t> by_position(own_.size());
  for (uint32_t i = 0; i < by_position.size(); ++i) by_position[i] = i;
  std::sort(by_position.begin(), by_position.end(),
            [&](uint32_t a, uint32_t b) { return std::tie(own_[a].at, a) < std::tie(own_[b].at, b); });
  // Votes (owner's label, halo's label) and, per (owner tile, halo label), the halo points of
  // that label the owner tile holds on any surface.
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> votes;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> seen;    // (owner tile, halo label)
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> shown;   // (owner label, halo tile)
  uint64_t matched = 0;
  for (const Point& h : halo_) {
    const auto it = std::lower_bound(by_position.begin(), by_position.end(), h.at,
                                     [&](uint32_t a, const std::array<double, 3>& at) {
                                       return own_[a].at < at;
                                     });
    if (it == by_position.end() || own_[*it].at != h.at) continue;
    const uint32_t owner = own_[*it].label;
    if (owner == kNoSurface) continue;
    ++matched;
    ++votes[{owner, h.label}];
    ++seen[{tile_of_label_[owner], h.label}];
    ++shown[{owner, tile_of_label_[h.label]}];
  }
  std::vector<uint32_t> parent(labels);
  for (uint32_t l = 0; l < labels; ++l) parent[l] = l;
  uint32_t joins = 0;
  for (const auto& [pair, count] : votes) {
    const uint32_t of = seen[{tile_of_label_[pair.first], pair.second}];
    const uint32_t of_owner = shown[{pair.first, tile_of_label_[pair.second]}];
    if (count >= kMinVotes && 2 * uint64_t{count} >= of && 2 * uint64_t{count} >= of_owner) {
      joins += find_root(parent, pair.first) != find_root(parent, pair.second);
      unite(parent, pair.first, pair.second);
    }
  }
  // Ids in the order of each joined surface's first own point.
  Segmentation out;
  out.surface.resize(own_.size(), kNoSurface);
  std::vector<uint32_t> id(labels, kNoSurface);
  for (std::size_t i = 0; i < own_.size(); ++i) {
    if (own_[i].label == kNoSurface) continue;
    uint32_t& s = id[find_root(parent, own_[i].label)];
    if (s == kNoSurface) {
      s = out.count();
      out.sizes.push_back(0);
    }
    out.surface[i] = s;
    ++out.sizes[s];
  }
  if (info) *info = {halo_.size(), matched, labels, joins};
  return out;
}

}  // namespace splatkit::graph
