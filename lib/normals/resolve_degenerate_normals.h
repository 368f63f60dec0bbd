// resolve_degenerate_normals: normals for points whose k-neighbourhood is degenerate (fewer than 3
// distinct points, or collinear — see neighborhood_pca.h), taken from a wider neighbourhood.
//
// For each listed point the neighbourhood grows (4k, 16k, 64k nearest points, capped at the cloud
// size and at max(kMaxWideK, 4k)) until it is no longer degenerate and, up to 16k points, no
// longer a thread (is_thread in neighborhood_pca.h: it reaches the next scan lines); that PCA's
// normal is used. When even the widest one is degenerate (a thread of points along a line, or the whole cloud
// collinear or a single position), a fallback keeps the result defined: for a line, the unit vector
// perpendicular to it closest to +z (+x when the line is along z); for a single position, (0, 0,
// 1). A radius of 0 (a point whose row held only its own duplicates) is recomputed from the wider
// row the same way. Deterministic; runs in parallel over the listed points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "normals/neighborhood_pca.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

inline constexpr std::size_t kMaxWideK = 1024;

struct DegenerateStats {
  std::size_t resolved = 0;    // got a normal from a wider, non-degenerate neighbourhood
  std::size_t unresolved = 0;  // got the fallback normal
};

// When `positions` is a piece of a larger cloud: the whole cloud's size and PCA, which the cap on
// the neighbourhood's size and the test for a wholly degenerate cloud use.
struct WholeCloud {
  std::size_t size = 0;
  PcaNormal pca;
};

// The whole cloud's PCA (neighborhood_pca over every point).
PcaNormal whole_cloud_pca(std::span<const Vec3f> positions);

// index: built over `positions` (#N). points: the indices to fix. normals, radii: #N, updated for
// the listed points only (radii before any scaling). k, radius_k as in NormalOptions. whole: null
// when `positions` is the whole cloud. sq_reach (empty, or #N) receives, for each listed point,
// the squared distance of the farthest neighbour its widest query returned (0 when the cloud was
// degenerate as a whole and no query ran). bridges (empty, or one per entry of `points`) receives
// for each listed point the nearest point of its widest neighbourhood more than 45° off the
// direction of its own k nearest (the next scan line's), or kNoBridge.
inline constexpr uint32_t kNoBridge = 0xFFFFFFFFu;
struct Bridge {  // an edge from a thread point to the next scan line
  uint32_t from, to;
};
DegenerateStats resolve_degenerate_normals(
    const SpatialIndex& index, std::span<const Vec3f> positions, std::span<const uint32_t> points,
    std::size_t k, std::size_t radius_k, std::span<Vec3f> normals, std::span<float> radii,
    const WholeCloud* whole = nullptr, std::span<float> sq_reach = {},
    std::span<uint32_t> bridges = {});

// The fallback normal for a degenerate set whose principal axis is `axis` and largest eigenvalue
// `largest` (0: a single position).
Vec3f fallback_normal(const Vec3f& axis, double largest);

}  // namespace splatkit
