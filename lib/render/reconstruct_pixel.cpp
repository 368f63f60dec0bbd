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

PixelRay pixel_ray(const Projection& projection, int x, int y) {
  const float inv_f = 1.0f / projection.focal_px;
  return {(float(x) + 0.5f - projection.cx) * inv_f, (float(y) + 0.5f - projection.cy) * inv_f};
}

float depth_window(BlendMode mode, float epsilon, float max_radius, int capacity) {
  return mode == BlendMode::kZThreshold ? capacity * epsilon : (capacity + 1) * 2.0f * max_radius;
}

namespace {

// Keeps in `f` (front to back) only the fragments that face the eye when at least one does:
// a back face within the blend's reach of a front face (the far side of a thin part, the other
// wall of a crevice) would turn the blended normal away from the viewer. Returns the count kept.
inline int keep_front_faces(Fragment* f, int n, const SplatRaster* rasters) {
  int front = 0;
  for (int k = 0; k < n; ++k) front += rasters[f[k].splat].nc <= 0;
  if (front == 0 || front == n) return n;
  int kept = 0;
  for (int k = 0; k < n; ++k)
    if (rasters[f[k].splat].nc <= 0) f[kept++] = f[k];
  return kept;
}

// The fit's ridge term, relative to the weighted mean squared radius (reconstruct_pixel.h): small
// enough that a sphere sampled at random keeps a fraction of a degree of error, large enough that
// two or three nearly collinear centres fall back to the weighted mean.
inline constexpr float kRidge = 0.01f;

// Blends the fragments f[0..n) into `out` (n >= 1): colour and depth by their weighted means, the
// normal by the weighted least-squares fit of reconstruct_pixel.h, all in one pass over the
// fragments. The centres' offsets (a, b) are camera-space x and y measured from the ray's point at
// the nearest fragment's depth z0; the fit is evaluated at the ray's point at the blended depth z̄,
// which lies (z̄ − z0)·ray off that origin. With the centred moments (covariance C of the offsets
// plus the ridge, cross-covariance N of normals and offsets), the slopes are G = N C⁻¹ and the
// normal n̄ + G (p − m̄), p the evaluation point and m̄ the weighted mean offset.
// Four float lanes (GCC and Clang vector extension: SSE on x86-64, plain code elsewhere): each
// sum below stays in one register. Lane by lane the same operations as scalar code.
typedef float Lanes4 __attribute__((vector_size(16)));

inline void blend(const Fragment* f, int n, const DrawList& draws, const SplatRaster* rasters,
                  const Vec3f& default_albedo, const PixelRay& ray, PixelSurface& out) {
  const float z0 = f[0].depth, x0 = z0 * ray.x, y0 = z0 * ray.y;
  // Sums of w·(n, 1), w·(n, 1)·a, w·(n, 1)·b, w·(a², ab, b², z), w·(albedo, r²).
  Lanes4 s1 = {}, sa = {}, sb = {}, sq = {}, sc = {};
  for (int k = 0; k < n; ++k) {
    const SplatRaster& r = rasters[f[k].splat];
    const float w = f[k].weight, a = r.cx - x0, b = r.cy - y0;
    const Vec3f c = draws.colors ? draws.colors[f[k].splat] : default_albedo;
    const Lanes4 wn = Lanes4{r.normal.x, r.normal.y, r.normal.z, 1.0f} * w;
    s1 += wn;
    sa += wn * a;
    sb += wn * b;
    sq += Lanes4{a * a, a * b, b * b, f[k].depth} * w;
    sc += Lanes4{c.x, c.y, c.z, r.radius * r.radius} * w;
  }
  // Opaque splats: the first surface covers the pixel fully, so compositing (eq. 5.1) stops here.
  const float inv = 1.0f / s1[3];
  out.albedo = Vec3f{sc[0], sc[1], sc[2]} * inv;
  out.depth = sq[3] * inv;
  out.alpha = 1.0f;
  const Vec3f mean = Vec3f{s1[0], s1[1], s1[2]} * inv;
  out.normal = mean;
  if (n < 2) return;
  const float ma = sa[3] * inv, mb = sb[3] * inv, ridge = kRidge * sc[3];
  const float caa = sq[0] - sa[3] * ma + ridge, cbb = sq[2] - sb[3] * mb + ridge;
  const float cab = sq[1] - sa[3] * mb;
  const float det = caa * cbb - cab * cab;
  if (!(det > 0)) return;
  // G e = N C⁻¹ e with e the evaluation point's offset from the mean offset.
  const float dz = out.depth - z0;
  const float ea = dz * ray.x - ma, eb = dz * ray.y - mb;
  const float inv_det = 1.0f / det;
  const float p = (cbb * ea - cab * eb) * inv_det, q = (caa * eb - cab * ea) * inv_det;
  const Vec3f na = Vec3f{sa[0], sa[1], sa[2]} - mean * sa[3];
  const Vec3f nb = Vec3f{sb[0], sb[1], sb[2]} - mean * sb[3];
  out.normal = mean + na * p + nb * q;
}

[[gnu::always_inline]] inline PixelSurface reconstruct(const float* depths, const float* weights,
                                                       const uint32_t* splats, int count,
                                                       const DrawList& draws,
                                                       const SplatRaster* rasters,
                                                       const BlendOptions& options,
                                                       const Vec3f& default_albedo,
                                                       const PixelRay& ray) {
  PixelSurface out;
  if (count <= 0) return out;
  Fragment f[kMaxFragmentsPerPixel];
  sort_front_to_back(depths, weights, splats, count, f);
  const float limit = f[0].depth + options.window;
  while (count > 1 && f[count - 1].depth > limit) --count;
  out.surface_id = draws.surface_ids ? draws.surface_ids[f[0].splat] : 0;
  int joined;
  if (draws.surface_ids == nullptr) {
    joined = first_run(f, count, rasters, options);
  } else {
    bool marks[kMaxFragmentsPerPixel] = {};
    first_surface(f, count, 0, draws, rasters, options, marks);
    joined = 0;
    for (int k = 0; k < count; ++k)
      if (marks[k]) f[joined++] = f[k];
  }
  blend(f, keep_front_faces(f, joined, rasters), draws, rasters, default_albedo, ray, out);
  return out;
}

}  // namespace

PixelSurface reconstruct_pixel(const float* depths, const float* weights, const uint32_t* splats,
                               int count, const DrawList& draws, const SplatRaster* rasters,
                               const BlendOptions& options, const Vec3f& default_albedo,
                               const PixelRay& ray) {
  return reconstruct(depths, weights, splats, count, draws, rasters, options, default_albedo, ray);
}

int reconstruct_pixels(const FragmentStore& store, int pixels, const DrawList& draws,
                       const SplatRaster* rasters, const BlendOptions& options,
                       const Vec3f& default_albedo, const TilePixels& tile, PixelSurface* out,
                       uint64_t& overflowed) {
  int covered = 0;
  for (int p = 0; p < pixels; ++p) {
    const int n = store.count(p);
    if (n == 0) {
      out[p].alpha = 0;
      continue;
    }
    const PixelRay ray =
        pixel_ray(*tile.projection, tile.x0 + p % tile.width, tile.y0 + p / tile.width);
    out[p] = reconstruct(store.depths(p), store.weights(p), store.splats(p), n, draws, rasters,
                         options, default_albedo, ray);
    ++covered;
    overflowed += store.overflowed(p);
  }
  return covered;
}

}  // namespace splatkit::render
