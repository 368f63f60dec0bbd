#include "render/reconstruct_pixel.h"

#include <algorithm>
#include <cmath>
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

// A list of fragments as the FragmentStore keeps them.
struct FragmentList {
  const float* depths;
  const float* weights;
  const uint32_t* splats;
  int count;
};

// Copies the fragments of `a` and `b` (the disc and the ring slots of a pixel) into `f` as one
// list, sorted front to back (depth, ties by splat index), by rank: fragment i goes to the slot
// counting the fragments nearer than it. An insertion sort mispredicted about once per fragment,
// since the arrival order (splat order) says nothing about depth; counting the n² comparisons of
// one integer key takes a compare and an add with carry each and no branch but the loops over n.
// A splat adds at most one fragment to a pixel (disc or ring), so the keys are unique and the
// ranks a permutation.
inline void sort_front_to_back(const FragmentList& a, const FragmentList& b, Fragment* f) {
  const int n = a.count + b.count;
  uint64_t key[kMaxFragmentsPerPixel + kRingSlots];
  for (int i = 0; i < a.count; ++i) key[i] = sort_key(a.depths[i], a.splats[i]);
  for (int i = 0; i < b.count; ++i) key[a.count + i] = sort_key(b.depths[i], b.splats[i]);
  for (int i = 0; i < n; ++i) {
    int rank = 0;
    for (int j = 0; j < n; ++j) rank += key[j] < key[i];
    const FragmentList& l = i < a.count ? a : b;
    const int k = i < a.count ? i : i - a.count;
    f[rank] = {l.depths[k], l.weights[k], l.splats[k]};
  }
}

// The surface that holds fragment f[c] (a disc fragment): the run of sorted fragments around it
// that the blend rule chains, forward and backward from it (ring fragments in front of the disc
// join when the rule reaches them). Returns [lo, hi).
struct Run {
  int lo, hi;
};

Run surface_run(const Fragment* f, int n, int c, const SplatRaster* rasters,
                const BlendOptions& options) {
  int lo = c, hi = c + 1;
  if (options.mode == BlendMode::kZThreshold) {
    while (hi < n && f[hi].depth - f[hi - 1].depth < options.epsilon) ++hi;
    while (lo > 0 && f[lo].depth - f[lo - 1].depth < options.epsilon) --lo;
  } else {
    const SplatRaster& first = rasters[f[c].splat];
    float range_end = first.zmax, range_begin = first.zmin;
    for (; hi < n; ++hi) {
      const SplatRaster& r = rasters[f[hi].splat];
      if (r.zmin > range_end) break;
      range_end = std::max(range_end, r.zmax);
    }
    for (; lo > 0; --lo) {
      const SplatRaster& r = rasters[f[lo - 1].splat];
      if (r.zmax < range_begin) break;
      range_begin = std::min(range_begin, r.zmin);
    }
  }
  return {lo, hi};
}

}  // namespace

PixelRay pixel_ray(const Projection& projection, int x, int y) {
  const float inv_f = 1.0f / projection.focal_px;
  return {(float(x) + 0.5f - projection.cx) * inv_f, (float(y) + 0.5f - projection.cy) * inv_f};
}

float depth_window(BlendMode mode, float epsilon, float max_radius, int capacity) {
  return mode == BlendMode::kZThreshold ? capacity * epsilon
                                        : (capacity + 1) * 2.0f * kRingScale * max_radius;
}

namespace {

// Keeps in `f` (front to back) only the fragments that face the eye when a disc fragment does:
// a back face within the blend's reach of a front face (the far side of a thin part, the other
// wall of a crevice) would turn the blended normal away from the viewer. Keeps at least one disc
// fragment. Returns the count kept.
template <bool kRings>
inline int keep_front_faces(Fragment* f, int n, const SplatRaster* rasters) {
  int front = 0, front_discs = 0;
  for (int k = 0; k < n; ++k) {
    const bool facing = rasters[f[k].splat].nc <= 0;
    front += facing;
    if constexpr (kRings) front_discs += facing & (f[k].weight > 0);
  }
  if constexpr (!kRings) front_discs = front;
  if (front_discs == 0 || front == n) return n;
  int kept = 0;
  for (int k = 0; k < n; ++k)
    if (rasters[f[k].splat].nc <= 0) f[kept++] = f[k];
  return kept;
}

// Whether the centres of the splats of f[0..n) (ring fragments of one surface, n <= 8 or so)
// surround the pixel's ray, seen along it: their directions from the ray's point at f[0]'s depth
// (camera-space x, y) leave no gap of half a turn or more. Then the pixel lies in a hole among
// those splats (where a cover of discs leaves a gap between three), not beyond the edge of their
// surface, where the centres lie all on one side.
bool surrounded(const Fragment* f, int n, const SplatRaster* rasters, const PixelRay& ray) {
  if (n < 3) return false;
  const float x0 = f[0].depth * ray.x, y0 = f[0].depth * ray.y;
  float angle[kMaxFragmentsPerPixel + kRingSlots] = {};
  for (int k = 0; k < n; ++k) {
    const SplatRaster& r = rasters[f[k].splat];
    float a = std::atan2(r.cy - y0, r.cx - x0);
    int j = k;
    for (; j > 0 && angle[j - 1] > a; --j) angle[j] = angle[j - 1];
    angle[j] = a;
  }
  constexpr float kPi = 3.14159265f;
  float gap = angle[0] + 2 * kPi - angle[n - 1];
  for (int k = 1; k < n; ++k) gap = std::max(gap, angle[k] - angle[k - 1]);
  return gap < kPi;
}

// Whether the ring fragments f[0..n) all face the eye and the disc fragment f[c] (c < count, or
// none) faces away.
bool behind_away(const Fragment* f, int n, int c, int count, const SplatRaster* rasters) {
  if (c < count && !(rasters[f[c].splat].nc > 0)) return false;
  for (int k = 0; k < n; ++k)
    if (rasters[f[k].splat].nc > 0) return false;
  return c < count;
}

// The fit's ridge term, relative to the trace of the offsets' covariance (reconstruct_pixel.h):
// small enough that a sphere sampled at random keeps a tenth of a degree of error, large enough
// that nearly collinear centres give no slope across their line.
inline constexpr float kRidge = 0.02f;

// Four float lanes (GCC and Clang vector extension: SSE on x86-64, plain code elsewhere): each
// sum below stays in one register. Lane by lane the same operations as scalar code.
typedef float Lanes4 __attribute__((vector_size(16)));

// Blends the fragments f[0..n) (at least one disc fragment unless `rings_cover`) into `out`:
// colour and depth by the disc fragments' weighted means (every fragment's with `rings_cover`), the
// normal by the weighted least-squares fit of reconstruct_pixel.h over disc and ring fragments, in
// one pass. The centres' offsets (a, b) are camera-space x and y measured from the ray's point at
// the first fragment's depth z0; the fit is evaluated at the ray's point at the blended depth z̄, (z̄
// − z0)·ray off that origin. With the centred moments (covariance C of the offsets plus the ridge,
// cross-covariance N of normals and offsets) the slopes are G = N C⁻¹, and the normal is n̄ + G (p −
// m̄), p the evaluation point and m̄ the weighted mean offset.
template <bool kFit, bool kRings>
inline void blend(const Fragment* f, int n, const DrawList& draws, const SplatRaster* rasters,
                  const Vec3f& default_albedo, const PixelRay& ray, bool rings_cover,
                  PixelSurface& out) {
  const float z0 = f[0].depth, x0 = z0 * ray.x, y0 = z0 * ray.y;
  // Over every fragment, weight |w|: sums of w·(n, 1), w·(n, 1)·a, w·(n, 1)·b, w·(a², ab, b², 0).
  // Over the disc fragments: w·(albedo, 1) and w·z.
  Lanes4 s1 = {}, sa = {}, sb = {}, sq = {}, sc = {};
  float sz = 0;
  for (int k = 0; k < n; ++k) {
    const SplatRaster& r = rasters[f[k].splat];
    const float w = kRings ? std::fabs(f[k].weight) : f[k].weight;
    const float wd = !kRings || (f[k].weight > 0) | rings_cover ? w : 0.0f;
    const float a = r.cx - x0, b = r.cy - y0;
    const Vec3f c = draws.colors ? draws.colors[f[k].splat] : default_albedo;
    const Lanes4 wn = Lanes4{r.normal.x, r.normal.y, r.normal.z, 1.0f} * w;
    s1 += wn;
    if constexpr (kFit) {
      sa += wn * a;
      sb += wn * b;
      sq += Lanes4{a * a, a * b, b * b, 0.0f} * w;
    }
    sc += Lanes4{c.x, c.y, c.z, 1.0f} * wd;
    sz += f[k].depth * wd;
  }
  // Opaque splats: the first surface covers the pixel fully, so compositing (eq. 5.1) stops here.
  const float inv = 1.0f / s1[3];
  const float inv_d = kRings ? 1.0f / sc[3] : inv;
  out.albedo = Vec3f{sc[0], sc[1], sc[2]} * inv_d;
  out.depth = sz * inv_d;
  out.alpha = 1.0f;
  const Vec3f mean = Vec3f{s1[0], s1[1], s1[2]} * inv;
  out.normal = mean;
  if (!kFit || n < 2) return;
  const float ma = sa[3] * inv, mb = sb[3] * inv;
  const float vaa = sq[0] - sa[3] * ma, vbb = sq[2] - sb[3] * mb, ridge = kRidge * (vaa + vbb);
  const float caa = vaa + ridge, cbb = vbb + ridge, cab = sq[1] - sa[3] * mb;
  const float det = caa * cbb - cab * cab;
  if (!(det > 0)) return;
  // G (p − m̄) = N C⁻¹ e, e the evaluation point's offset from the mean offset.
  const float dz = out.depth - z0;
  const float ea = dz * ray.x - ma, eb = dz * ray.y - mb;
  const float inv_det = 1.0f / det;
  const float p = (cbb * ea - cab * eb) * inv_det, q = (caa * eb - cab * ea) * inv_det;
  const Vec3f na = Vec3f{sa[0], sa[1], sa[2]} - mean * sa[3];
  const Vec3f nb = Vec3f{sb[0], sb[1], sb[2]} - mean * sb[3];
  out.normal = mean + na * p + nb * q;
}

// kRings: the list may hold ring fragments (without, the same result in fewer steps).
template <bool kRings>
[[gnu::always_inline]] inline PixelSurface reconstruct(
    const FragmentList& discs, const FragmentList& rings, const DrawList& draws,
    const SplatRaster* rasters, const BlendOptions& options, const Vec3f& default_albedo,
    const PixelRay& ray) {
  PixelSurface out;
  int count = discs.count + rings.count;
  if (count <= 0) return out;
  Fragment f[kMaxFragmentsPerPixel + kRingSlots];
  sort_front_to_back(discs, rings, f);
  // The nearest disc fragment starts the front surface, unless ring fragments in front of it that
  // do not chain to it close a hole in their surface: where their splats surround the pixel, or
  // where they face the eye and that disc faces away (a back face seen through a front surface
  // can only be seen through a gap in it; at an open surface's edge, the ring widens the edge
  // by at most its width).
  int c = 0;
  if constexpr (kRings) {
    while (c < count && !(f[c].weight > 0)) ++c;
    if (c > 0) {
      const Run front = surface_run(f, count, 0, rasters, options);
      if (front.hi <= c &&
          (behind_away(f, front.hi, c, count, rasters) || surrounded(f, front.hi, rasters, ray))) {
        blend<true, true>(f, front.hi, draws, rasters, default_albedo, ray, true, out);
        out.surface_id = draws.surface_ids ? draws.surface_ids[f[0].splat] : 0;
        return out;
      }
    }
    if (c == count) return out;
  }
  // Pixels whose front surface starts with a splat under kRingMinPx in radius take the weighted
  // mean normal: its facets are a few pixels across, and the fit would cost a third of the
  // reconstruction again on scenes of such splats.
  const bool fit = rasters[f[c].splat].ring2 > 1.0f;
  const float limit = f[c].depth + options.window;
  while (f[count - 1].depth > limit) --count;
  if (draws.surface_ids != nullptr) {
    // Only the fragments of f[c]'s surface id chain and blend ([IvoMSc] §5.5).
    const uint32_t id = draws.surface_ids[f[c].splat];
    int kept = 0, first = 0;
    for (int k = 0; k < count; ++k) {
      if (k == c) first = kept;
      if (draws.surface_ids[f[k].splat] == id) f[kept++] = f[k];
    }
    count = kept;
    c = first;
    out.surface_id = id;
  }
  const Run run = surface_run(f, count, c, rasters, options);
  const int n = keep_front_faces<kRings>(f + run.lo, run.hi - run.lo, rasters);
  if (fit)
    blend<true, kRings>(f + run.lo, n, draws, rasters, default_albedo, ray, false, out);
  else
    blend<false, kRings>(f + run.lo, n, draws, rasters, default_albedo, ray, false, out);
  return out;
}

}  // namespace

PixelSurface reconstruct_pixel(const float* depths, const float* weights, const uint32_t* splats,
                               int count, const DrawList& draws, const SplatRaster* rasters,
                               const BlendOptions& options, const Vec3f& default_albedo,
                               const PixelRay& ray) {
  const FragmentList all{depths, weights, splats, count}, none{nullptr, nullptr, nullptr, 0};
  for (int k = 0; k < count; ++k)
    if (!(weights[k] > 0))
      return reconstruct<true>(all, none, draws, rasters, options, default_albedo, ray);
  return reconstruct<false>(all, none, draws, rasters, options, default_albedo, ray);
}

int reconstruct_pixels(const FragmentStore& store, int pixels, const DrawList& draws,
                       const SplatRaster* rasters, const BlendOptions& options,
                       const Vec3f& default_albedo, const TilePixels& tile, PixelSurface* out,
                       uint64_t& overflowed) {
  int covered = 0;
  for (int p = 0; p < pixels; ++p) {
    const int n = store.count(p);
    if (n + store.ring_count(p) == 0) {
      out[p].alpha = 0;
      continue;
    }
    const PixelRay ray =
        pixel_ray(*tile.projection, tile.x0 + p % tile.width, tile.y0 + p / tile.width);
    const FragmentList discs{store.depths(p), store.weights(p), store.splats(p), n};
    const int r0 = store.ring_offset();
    const FragmentList rings{discs.depths + r0, discs.weights + r0, discs.splats + r0,
                             store.ring_count(p)};
    out[p] = rings.count == 0
                 ? reconstruct<false>(discs, rings, draws, rasters, options, default_albedo, ray)
                 : reconstruct<true>(discs, rings, draws, rasters, options, default_albedo, ray);
    const bool hit = out[p].alpha > 0;  // not when only ring fragments reach the pixel
    covered += hit;
    overflowed += hit & store.overflowed(p);
  }
  return covered;
}

}  // namespace splatkit::render
