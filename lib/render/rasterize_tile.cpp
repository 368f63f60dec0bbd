#include "render/rasterize_tile.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "graph/make_clip_planes.h"

namespace splatkit::render {

namespace {

constexpr int kWeightTableSize = 1024;

constexpr float kRing2 = kRingScale * kRingScale;

// Sampled at the centres of kWeightTableSize equal steps of rho2 over [0, kRing2].
const std::array<float, kWeightTableSize + 1>& weight_table() {
  static const auto table = [] {
    std::array<float, kWeightTableSize + 1> t{};
    const float rim = std::exp(-kGaussianSharpness * kRing2);
    for (int i = 0; i <= kWeightTableSize; ++i) {
      const float rho2 = std::min(kRing2, (i + 0.5f) * kRing2 / kWeightTableSize);
      t[i] = std::exp(-kGaussianSharpness * rho2) - rim;
    }
    return t;
  }();
  return table;
}

}  // namespace

float gaussian_weight(float rho2) {
  return weight_table()[static_cast<int>(std::clamp(rho2, 0.0f, kRing2) *
                                         (kWeightTableSize / kRing2))];
}

namespace {

// Ray casts splat `index` over its box clipped to `tile`; returns the fragments stored. kClip:
// the splat has clip partners; each hit's scene point goes through the fragment test first and
// the discarded ones are counted in `clipped`. Both variants step L, U, V alike, so clipping
// changes nothing but the discarded fragments.
template <bool kClip, bool kRing>
inline uint64_t rasterize_splat(const SplatRaster& s, uint32_t index, const TileRect& tile,
                                const float* table, FragmentStore& store, const ClipContext* clip,
                                uint64_t& clipped) {
  const int stride = tile.width();
  const int xs = std::max<int>(s.x0, tile.x0), xe = std::min<int>(s.x1, tile.x1);
  const int ys = std::max<int>(s.y0, tile.y0), ye = std::min<int>(s.y1, tile.y1);
  const float di = float(xs - s.x0), dj = float(ys - s.y0);
  float l_row = s.l[0] * di + s.l[1] * dj + s.l[2];
  float u_row = s.u[0] * di + s.u[1] * dj + s.u[2];
  float v_row = s.v[0] * di + s.v[1] * dj + s.v[2];
  graph::ClipView view;
  if constexpr (kClip)
    view = graph::clip_view(*clip->table, {clip->planes, clip->table->partners.size()}, index);
  uint64_t fragments = 0;
  for (int y = ys; y <= ye; ++y) {
    float l = l_row, u = u_row, v = v_row;
    int pixel = (y - tile.y0) * stride + (xs - tile.x0);
    for (int x = xs; x <= xe; ++x, ++pixel) {
      const float q = u * u + v * v, l2 = l * l;
      if (q <= (kRing ? kRing2 : 1.0f) * l2 && l2 > 0) {
        const float inv = 1.0f / l;
        const float rho2 = q * inv * inv;
        const float depth = s.nc * inv;
        // Ring fragments carry their weight negated.
        float w = table[static_cast<int>(rho2 * (kWeightTableSize / kRing2))];
        if constexpr (kRing) w = rho2 <= 1.0f ? w : -w;
        // depth > 0: a ring that reaches the eye's plane meets some rays behind the eye (a disc
        // never does: setup_splats draws only discs beyond the near plane).
        bool keep = !kRing || depth > 0;
        if constexpr (kClip) {
          const Projection& pr = clip->projection;
          const Vec3f p = pr.eye + pr.ray(float(x) + 0.5f, float(y) + 0.5f) * depth;
          const bool discarded = graph::fragment_discarded(view, p);
          clipped += keep & discarded;
          keep = keep & !discarded;
        }
        if (keep) fragments += store.add(pixel, depth, w, index);
      }
      l += s.l[0];
      u += s.u[0];
      v += s.v[0];
    }
    l_row += s.l[1];
    u_row += s.u[1];
    v_row += s.v[1];
  }
  return fragments;
}

inline uint64_t rasterize_any(const SplatRaster& s, uint32_t index, const TileRect& tile,
                              const float* table, FragmentStore& store, const ClipContext* clip,
                              uint64_t& clipped) {
  const bool ring = s.ring2 > 1.0f;
  if (clip && clip->table->has_partners(index))
    return ring ? rasterize_splat<true, true>(s, index, tile, table, store, clip, clipped)
                : rasterize_splat<true, false>(s, index, tile, table, store, clip, clipped);
  return ring ? rasterize_splat<false, true>(s, index, tile, table, store, nullptr, clipped)
              : rasterize_splat<false, false>(s, index, tile, table, store, nullptr, clipped);
}

}  // namespace

RasterCounts rasterize_tile(const SplatRaster* rasters, const uint32_t* splats, std::size_t count,
                            const TileRect& tile, FragmentStore& store, const ClipContext* clip) {
  const float* table = weight_table().data();
  RasterCounts counts;
  // The tile's SplatRasters come from a large array written long before: prefetch a few splats
  // ahead (both cache lines of each) to hide the memory latency.
  constexpr std::size_t kAhead = 8;
  for (std::size_t k = 0; k < count; ++k) {
    if (k + kAhead < count) {
      const char* next = reinterpret_cast<const char*>(rasters + splats[k + kAhead]);
      __builtin_prefetch(next);
      __builtin_prefetch(next + sizeof(SplatRaster) - 1);
    }
    const SplatRaster& s = rasters[splats[k]];
    if (!(s.nc <= 0)) continue;
    counts.fragments += rasterize_any(s, splats[k], tile, table, store, clip, counts.clipped);
  }
  const float hidden_beyond = store.farthest_nearest(tile.width() * tile.height()) + store.window();
  for (std::size_t k = 0; k < count; ++k) {
    const SplatRaster& s = rasters[splats[k]];
    if (s.nc <= 0) continue;
    if (s.zmin > hidden_beyond) {
      ++counts.skipped_splats;
      continue;
    }
    counts.fragments += rasterize_any(s, splats[k], tile, table, store, clip, counts.clipped);
  }
  return counts;
}

}  // namespace splatkit::render
