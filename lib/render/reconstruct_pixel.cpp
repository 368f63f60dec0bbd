#include "render/reconstruct_pixel.h"

#include <algorithm>
#include <cstring>

namespace splatkit::render {

namespace {

struct Fragment {
  float depth, weight;
  uint32_t splat;
};

// (depth, splat) as one integer that orders like (depth, then splat index): the depth's bits
// made to order as unsigned integers (sign bit set for positive floats, every bit flipped for
// negative ones; −0 before +0, no NaNs here), the splat index below them.
inline uint64_t sort_key(float depth, uint32_t splat) {
  uint32_t b;
  std::memcpy(&b, &depth, sizeof b);
  b ^= (b >> 31) != 0 ? 0xffffffffu : 0x80000000u;
  return uint64_t{b} << 32 | splat;
}

// Copies the fragments into `f`, sorted front to back (depth, ties by splat index), by rank:
// fragment i goes to the slot counting the fragments nearer than it. An insertion sort
// mispredicted about once per fragment, since the arrival order (splat order) says nothing
// about depth; counting the n² comparisons of one integer key takes a compare and an add with
// carry each and no branch but the loops over n. A splat adds at most one fragment to a pixel,
// so the keys are unique and the ranks a permutation.
inline void sort_front_to_back(const float* depths, const float* weights, const uint32_t* splats,
                               int n, Fragment* f) {
  uint64_t key[kMaxFragmentsPerPixel];
  for (int i = 0; i < n; ++i) key[i] = sort_key(depths[i], splats[i]);
  for (int i = 0; i < n; ++i) {
    int rank = 0;
    for (int j = 0; j < n; ++j) rank += key[j] < key[i];
    f[rank] = {depths[i], weights[i], splats[i]};
  }
}

// Marks in `joined` the fragments of the surface that starts at f[first] (same surface id,
// chained by the blend rule); returns how many joined.
int first_surface(const Fragment* f, int n, int first, const DrawList& draws,
                  const SplatRaster* rasters, const BlendOptions& options, bool* joined) {
  const uint32_t id = draws.surface_ids ? draws.surface_ids[f[first].splat] : 0;
  joined[first] = true;
  int count = 1;
  float last = f[first].depth;
  float range_end = rasters[f[first].splat].zmax;
  for (int k = first + 1; k < n; ++k) {
    if (joined[k]) continue;
    if (draws.surface_ids && draws.surface_ids[f[k].splat] != id) continue;
    if (options.mode == BlendMode::kZThreshold) {
      if (!(f[k].depth - last < options.epsilon)) break;
      last = f[k].depth;
    } else {
      const SplatRaster& r = rasters[f[k].splat];
      if (r.zmin > range_end) break;
      range_end = std::max(range_end, r.zmax);
    }
    joined[k] = true;
    ++count;
  }
  return count;
}

// Without surface ids the first surface is the run of sorted fragments from f[0] that the blend
// rule chains, so first_surface's marks (every id equal) are a prefix; returns its length. Saves
// the marks and the blend loop's test of each, a branch that mispredicts often.
int first_run(const Fragment* f, int n, const SplatRaster* rasters, const BlendOptions& options) {
  int k = 1;
  if (options.mode == BlendMode::kZThreshold) {
    while (k < n && f[k].depth - f[k - 1].depth < options.epsilon) ++k;
  } else {
    float range_end = rasters[f[0].splat].zmax;
    for (; k < n; ++k) {
      const SplatRaster& r = rasters[f[k].splat];
      if (r.zmin > range_end) break;
      range_end = std::max(range_end, r.zmax);
    }
  }
  return k;
}

}  // namespace

float depth_window(BlendMode mode, float epsilon, float max_radius, int capacity) {
  return mode == BlendMode::kZThreshold ? capacity * epsilon : (capacity + 1) * 2.0f * max_radius;
}

namespace {

[[gnu::always_inline]] inline PixelSurface reconstruct(const float* depths, const float* weights,
                                                       const uint32_t* splats, int count,
                                                       const DrawList& draws,
                                                       const SplatRaster* rasters,
                                                       const BlendOptions& options,
                                                       const Vec3f& default_albedo) {
  PixelSurface out;
  if (count <= 0) return out;
  Fragment f[kMaxFragmentsPerPixel];
  sort_front_to_back(depths, weights, splats, count, f);
  const float limit = f[0].depth + options.window;
  while (count > 1 && f[count - 1].depth > limit) --count;
  Vec3f normal{0, 0, 0}, albedo{0, 0, 0};
  float depth = 0, weight = 0;
  auto blend = [&](const Fragment& g) {
    const float w = g.weight;
    normal += rasters[g.splat].normal * w;
    albedo += (draws.colors ? draws.colors[g.splat] : default_albedo) * w;
    depth += g.depth * w;
    weight += w;
  };
  if (draws.surface_ids == nullptr) {
    const int joined = first_run(f, count, rasters, options);
    for (int k = 0; k < joined; ++k) blend(f[k]);
  } else {
    bool joined[kMaxFragmentsPerPixel] = {};
    first_surface(f, count, 0, draws, rasters, options, joined);
    for (int k = 0; k < count; ++k)
      if (joined[k]) blend(f[k]);
  }
  // Opaque splats: the first surface covers the pixel fully, so compositing (eq. 5.1) stops here.
  const float inv = 1.0f / weight;
  out.normal = normal * inv;
  out.albedo = albedo * inv;
  out.depth = depth * inv;
  out.alpha = 1.0f;
  out.surface_id = draws.surface_ids ? draws.surface_ids[f[0].splat] : 0;
  return out;
}

}  // namespace

PixelSurface reconstruct_pixel(const float* depths, const float* weights, const uint32_t* splats,
                               int count, const DrawList& draws, const SplatRaster* rasters,
                               const BlendOptions& options, const Vec3f& default_albedo) {
  return reconstruct(depths, weights, splats, count, draws, rasters, options, default_albedo);
}

int reconstruct_pixels(const FragmentStore& store, int pixels, const DrawList& draws,
                       const SplatRaster* rasters, const BlendOptions& options,
                       const Vec3f& default_albedo, PixelSurface* out, uint64_t& overflowed) {
  int covered = 0;
  for (int p = 0; p < pixels; ++p) {
    const int n = store.count(p);
    if (n == 0) {
      out[p].alpha = 0;
      continue;
    }
    out[p] = reconstruct(store.depths(p), store.weights(p), store.splats(p), n, draws, rasters,
                         options, default_albedo);
    ++covered;
    overflowed += store.overflowed(p);
  }
  return covered;
}

}  // namespace splatkit::render
