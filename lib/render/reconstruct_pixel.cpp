#include "render/reconstruct_pixel.h"

#include <algorithm>

namespace splatkit::render {

namespace {

struct Fragment {
  float depth, weight;
  uint32_t splat;
};

inline bool nearer(const Fragment& a, const Fragment& b) {
  return a.depth < b.depth || (a.depth == b.depth && a.splat < b.splat);
}

// Insertion sort: counts are small and often nearly sorted.
inline void sort_front_to_back(Fragment* f, int n) {
  for (int i = 1; i < n; ++i) {
    Fragment x = f[i];
    int j = i - 1;
    for (; j >= 0 && nearer(x, f[j]); --j) f[j + 1] = f[j];
    f[j + 1] = x;
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

}  // namespace

float depth_window(BlendMode mode, float epsilon, float max_radius, int capacity) {
  return mode == BlendMode::kZThreshold ? capacity * epsilon : (capacity + 1) * 2.0f * max_radius;
}

PixelSurface reconstruct_pixel(const float* depths, const float* weights, const uint32_t* splats,
                               int count, const DrawList& draws, const SplatRaster* rasters,
                               const BlendOptions& options, const Vec3f& default_albedo) {
  PixelSurface out;
  if (count <= 0) return out;
  Fragment f[kMaxFragmentsPerPixel];
  bool joined[kMaxFragmentsPerPixel] = {};
  for (int k = 0; k < count; ++k) f[k] = {depths[k], weights[k], splats[k]};
  sort_front_to_back(f, count);
  const float limit = f[0].depth + options.window;
  while (count > 1 && f[count - 1].depth > limit) --count;
  first_surface(f, count, 0, draws, rasters, options, joined);
  Vec3f normal{0, 0, 0}, albedo{0, 0, 0};
  float depth = 0, weight = 0;
  for (int k = 0; k < count; ++k) {
    if (!joined[k]) continue;
    const float w = f[k].weight;
    normal += rasters[f[k].splat].normal * w;
    albedo += (draws.colors ? draws.colors[f[k].splat] : default_albedo) * w;
    depth += f[k].depth * w;
    weight += w;
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

}  // namespace splatkit::render
