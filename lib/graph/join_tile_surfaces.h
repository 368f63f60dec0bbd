// join_tile_surfaces: one set of surface ids over the tiles of a survey, each tile segmented on
// its own (splat-tile, then estimate-normals, build-splat-graph and segment-surfaces per tile).
// A tile's halo holds points that another tile owns, with the surface ids its own run gave them.
// Surface a of tile A and surface b of tile B are one surface, and join, where the points of B's
// halo that lie on b in B and on a in A are at least kMinVotes, at least half of B's halo points on
// b that A owns, and at least half of B's halo points that A has on a: each tile sees mostly the
// other's surface where its halo overlaps it. Joins chain (union-find). The result numbers the
// tiles' own points, gathered in the order they are added, as segment-surfaces numbers a cloud's:
// ids in the order of each surface's first point. Surfaces that no tile holds together (pieces
// that a whole run joins for being coplanar, with no splat between them) stay apart.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "graph/segment_surfaces.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct TileJoinInfo {
  uint64_t halo_points = 0;    // halo points with a surface id
  uint64_t matched = 0;        // of those, found among the tiles' own points with a surface id
  uint32_t tile_surfaces = 0;  // surfaces over all tiles before the join
  uint32_t joins = 0;          // pairs of surfaces joined
};

class TileSurfaceJoin {
 public:
  // Votes a join needs at least: a surface that touches another's halo at a crease with a point
  // or two keeps apart.
  static constexpr uint32_t kMinVotes = 3;

  // Adds a tile: positions in its frame (file coordinates origin + p, compared exactly, so tiles
  // cut from one survey by splat-tile match wherever they share a frame), `own` the indices of its
  // own points (ascending; the rest are its halo), `surface` #N ids < `count` or kNoSurface.
  // The tile's own points follow those of the tiles added before.
  void add_tile(const std::array<double, 3>& origin, std::span<const Vec3f> positions,
                std::span<const uint32_t> own, std::span<const uint32_t> surface, uint32_t count);

  // The joined ids of all own points, in the order added.
  Segmentation finish(TileJoinInfo* info = nullptr);

 private:
  struct Point {
    std::array<double, 3> at;
    uint32_t label;  // over all tiles (base of the tile + its id), or kNoSurface
  };
  std::vector<Point> own_;   // every own point, in the order added
  std::vector<Point> halo_;  // halo points with a surface id
  std::vector<uint32_t> tile_of_label_;
  uint32_t tiles_ = 0;
};

}  // namespace splatkit::graph
