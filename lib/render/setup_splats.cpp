#include "render/setup_splats.h"

#include <algorithm>
#include <cmath>

#include "splatkit/simd_level.h"

namespace splatkit::render {

namespace {

// Per-frame constants. Camera-space pixel coordinates are relative to the principal point:
// pixel (i, j) has its centre at X = i + 0.5 - cx, Y = j + 0.5 - cy, and its ray is
// (X / f, Y / f, 1) in camera space.
struct FrameConstants {
  Vec3f eye, right, down, forward;
  float f, inv_f, cx, cy, near;
  int width, height;
};

FrameConstants frame_constants(const Projection& p) {
  return {p.eye, p.right, p.down, p.forward, p.focal_px, 1.0f / p.focal_px,
          p.cx,  p.cy,    p.near, p.width,   p.height};
}

inline void not_drawn(SplatRaster& s) {
  s.x0 = 1;
  s.x1 = 0;
  s.y0 = s.y1 = 0;
}

constexpr int kBlock = 64;

// By value (std::min/max/clamp return references, which keep GCC from vectorising the loop).
inline float min_f(float a, float b) { return a < b ? a : b; }
inline float max_f(float a, float b) { return a > b ? a : b; }

// ceil/floor for |v| < 2^23 without libm calls (baseline x86-64 has no rounding instructions).
inline float fast_floor(float v) {
  const float t = static_cast<float>(static_cast<int>(v));
  return t > v ? t - 1.0f : t;
}
inline float fast_ceil(float v) {
  const float t = static_cast<float>(static_cast<int>(v));
  return t < v ? t + 1.0f : t;
}

// The same values, for targets with rounding instructions (SSE4.1 and up: the AVX2 path). There
// GCC turns the pattern above into a branch that stops the loop from vectorising, and std::floor
// compiles to one instruction.
template <bool kRoundInsn>
inline float floor_small(float v) {
  if constexpr (kRoundInsn) return std::floor(v);
  return fast_floor(v);
}
template <bool kRoundInsn>
inline float ceil_small(float v) {
  if constexpr (kRoundInsn) return std::ceil(v);
  return fast_ceil(v);
}

// One block of splats as structure of arrays: inputs transposed first, then the branch-free
// arithmetic in a loop the compiler vectorises, then packing into SplatRaster.
struct Block {
  float px[kBlock], py[kBlock], pz[kBlock], nx[kBlock], ny[kBlock], nz[kBlock], r[kBlock];
  float ux[kBlock], uy[kBlock], uz[kBlock], rv[kBlock];  // elliptic splats: axis u, minor radius
  float nc[kBlock], zmin[kBlock], zmax[kBlock], ok[kBlock], cx[kBlock], cy[kBlock];
  float ring2[kBlock];
  float x0[kBlock], x1[kBlock], y0[kBlock], y1[kBlock];
  float l[3][kBlock], u[3][kBlock], v[3][kBlock];
};

// Extent along one image axis of the projected disc: the tangent lines X = Xc + t of the dual
// conic solve A t² + 2 B t + C = 0, with everything divided by r² and taken relative to the
// projected centre Xc = f c_x / c_z, so that no large terms cancel:
//   A = 1 − n_z² − (c_z / r)²,  B = (1 − n_z²) Xc + f n_x n_z,
//   C = (1 − n_z²) Xc² + 2 f n_x n_z Xc + f² (1 − n_x²).
// Gives the first and last pixel whose centre lies between the two roots (not yet clipped to
// the image).
template <bool kRoundInsn>
inline void axis_range(float centre, float n_axis, float nz, float one_minus_nz2, float inv_a,
                       float a, float f, float principal, float& first, float& last) {
  const float fnn = f * n_axis * nz;
  const float b = one_minus_nz2 * centre + fnn;
  const float c =
      one_minus_nz2 * centre * centre + 2 * fnn * centre + f * f * (1 - n_axis * n_axis);
  const float s = std::sqrt(max_f(0.0f, b * b - a * c));
  const float mid = principal + centre - b * inv_a;
  const float half = std::fabs(s * inv_a);
  // Clamped before rounding: far off-screen boxes must not overflow the int conversion.
  first = ceil_small<kRoundInsn>(min_f(max_f(mid - half - 0.5f, -2.0f), 32768.0f));
  last = floor_small<kRoundInsn>(min_f(max_f(mid + half - 0.5f, -2.0f), 32768.0f));
}

// Extent along one image axis of a projected ellipse with camera-space centre c, semi-axes ra
// along a and rb along b (unit, in its plane). The tangent lines x = xc + t (normalised image
// coordinates, xc = c_x / c_z) of the dual conic ra² aaᵀ + rb² bbᵀ − ccᵀ solve
//   A t² + 2 B t + C = 0,  A = ra² a_z² + rb² b_z² − c_z²,  B = −(ra² α a_z + rb² β b_z),
//   C = ra² α² + rb² β²,  α = a_x − xc a_z,  β = b_x − xc b_z
// (with x, a_x, b_x, c_x the components along the image axis). For a circle (ra = rb) this is
// axis_range's conic.
template <bool kRoundInsn>
inline void ellipse_axis_range(float xc, float ax, float az, float bx, float bz, float ra2,
                               float rb2, float a, float f, float principal, float& first,
                               float& last) {
  const float alpha = ax - xc * az, beta = bx - xc * bz;
  const float b = -(ra2 * alpha * az + rb2 * beta * bz);
  const float c = ra2 * alpha * alpha + rb2 * beta * beta;
  const float inv_a = 1.0f / a;
  const float s = std::sqrt(max_f(0.0f, b * b - a * c));
  const float mid = principal + f * (xc - b * inv_a);
  const float half = f * std::fabs(s * inv_a);
  first = ceil_small<kRoundInsn>(min_f(max_f(mid - half - 0.5f, -2.0f), 32768.0f));
  last = floor_small<kRoundInsn>(min_f(max_f(mid + half - 0.5f, -2.0f), 32768.0f));
}

void transpose_block(const DrawList& draws, const FrameConstants& k, std::size_t begin, int count,
                     Block& b) {
  for (int i = 0; i < count; ++i) {
    const Vec3f p = draws.positions[begin + i] - k.eye, n = draws.normals[begin + i];
    b.px[i] = p.x, b.py[i] = p.y, b.pz[i] = p.z;
    b.nx[i] = n.x, b.ny[i] = n.y, b.nz[i] = n.z;
    b.r[i] = draws.radii[begin + i];
  }
  if (draws.axes == nullptr) return;
  for (int i = 0; i < count; ++i) {
    const Vec3f u = draws.axes[begin + i];
    b.ux[i] = u.x, b.uy[i] = u.y, b.uz[i] = u.z;
    b.rv[i] = draws.minor_radii[begin + i];
  }
}

// The block's arithmetic. Always inlined, so that each caller below compiles it for its own
// instruction set.
template <bool kEllipse, bool kRoundInsn>
[[gnu::always_inline]] inline void setup_lanes(const FrameConstants& k, bool cull_backfaces,
                                               int count, Block& b) {
  for (int i = 0; i < count; ++i) {
    const Vec3f cw{b.px[i], b.py[i], b.pz[i]}, nw{b.nx[i], b.ny[i], b.nz[i]};
    const Vec3f c{dot(cw, k.right), dot(cw, k.down), dot(cw, k.forward)};
    const Vec3f n{dot(nw, k.right), dot(nw, k.down), dot(nw, k.forward)};
    const float r = b.r[i];
    const float nc = dot(n, c);
    const float one_minus_nz2 = max_f(0.0f, 1.0f - n.z * n.z);
    // Disc axes in camera space: the ellipse's own (u, n × u), or for a circle any orthonormal
    // pair (branchless basis, Duff et al. 2017).
    Vec3f ax, ay;
    float rv = r;
    if constexpr (kEllipse) {
      const Vec3f uw{b.ux[i], b.uy[i], b.uz[i]};
      ax = {dot(uw, k.right), dot(uw, k.down), dot(uw, k.forward)};
      ay = cross(n, ax);
      rv = b.rv[i];
    } else {
      const float sign = n.z >= 0 ? 1.0f : -1.0f;
      const float sd = -1.0f / (sign + n.z);
      const float t = n.x * n.y * sd;
      ax = {1.0f + sign * n.x * n.x * sd, sign * t, -sign * n.x};
      ay = {t, sign + n.y * n.y * sd, -n.y};
    }
    const float half_depth = kEllipse ? std::sqrt(r * r * ax.z * ax.z + rv * rv * ay.z * ay.z)
                                      : r * std::sqrt(one_minus_nz2);
    // Bitwise & and |, not && and ||: no branches, so the loop vectorises. Splats that fail
    // `front` still run through the arithmetic (on a safe depth) and are dropped when packing.
    const bool front = (c.z - half_depth > k.near) & !(cull_backfaces & (nc > 0));
    const float cz = front ? c.z : 1.0f;
    const float inv_r = 1.0f / r, inv_z = 1.0f / cz;
    // The ring out to kRingScale × the radii (rasterize_tile.h) for splats over kRingMinPx in
    // radius whose ring lies wholly beyond the near plane (the box formula needs the whole figure
    // in front of the eye); the box takes it in.
    const bool ring = (r * k.f * inv_z > kRingMinPx) & (c.z - kRingScale * half_depth > k.near);
    const float box_scale = ring ? kRingScale : 1.0f;
    float x0, x1, y0, y1;
    if constexpr (kEllipse) {
      const float ra2 = r * r * (box_scale * box_scale), rb2 = rv * rv * (box_scale * box_scale);
      const float a = min_f(ra2 * ax.z * ax.z + rb2 * ay.z * ay.z - cz * cz, -1e-12f * ra2);
      ellipse_axis_range<kRoundInsn>(c.x * inv_z, ax.x, ax.z, ay.x, ay.z, ra2, rb2, a, k.f, k.cx,
                                     x0, x1);
      ellipse_axis_range<kRoundInsn>(c.y * inv_z, ax.y, ax.z, ay.y, ay.z, ra2, rb2, a, k.f, k.cy,
                                     y0, y1);
    } else {
      const float depth_ratio = cz * inv_r / box_scale;
      const float a = min_f(one_minus_nz2 - depth_ratio * depth_ratio, -1e-12f);
      const float inv_a = 1.0f / a;
      axis_range<kRoundInsn>(k.f * c.x * inv_z, n.x, n.z, one_minus_nz2, inv_a, a, k.f, k.cx, x0,
                             x1);
      axis_range<kRoundInsn>(k.f * c.y * inv_z, n.y, n.z, one_minus_nz2, inv_a, a, k.f, k.cy, y0,
                             y1);
    }
    x0 = max_f(x0, 0.0f);
    y0 = max_f(y0, 0.0f);
    x1 = min_f(x1, float(k.width - 1));
    y1 = min_f(y1, float(k.height - 1));
    b.ok[i] = (front & (x0 <= x1) & (y0 <= y1)) ? 1.0f : 0.0f;
    // The linear functions at the box corner.
    const Vec3f wu = (ax * nc - n * dot(ax, c)) * inv_r;
    const Vec3f wv = (ay * nc - n * dot(ay, c)) * (1.0f / rv);
    const float dx = (x0 + 0.5f - k.cx) * k.inv_f, dy = (y0 + 0.5f - k.cy) * k.inv_f;
    b.l[0][i] = n.x * k.inv_f;
    b.l[1][i] = n.y * k.inv_f;
    b.l[2][i] = n.x * dx + n.y * dy + n.z;
    b.u[0][i] = wu.x * k.inv_f;
    b.u[1][i] = wu.y * k.inv_f;
    b.u[2][i] = wu.x * dx + wu.y * dy + wu.z;
    b.v[0][i] = wv.x * k.inv_f;
    b.v[1][i] = wv.y * k.inv_f;
    b.v[2][i] = wv.x * dx + wv.y * dy + wv.z;
    b.nc[i] = nc;
    b.cx[i] = c.x;
    b.cy[i] = c.y;
    b.zmin[i] = c.z - box_scale * half_depth;
    b.zmax[i] = c.z + box_scale * half_depth;
    b.ring2[i] = box_scale * box_scale;
    b.x0[i] = x0;
    b.x1[i] = x1;
    b.y0[i] = y0;
    b.y1[i] = y1;
  }
}

// Two compilations of the same loop, the same float operations lane by lane (no contraction
// into fused multiply-adds: -ffp-contract=off, and no "fma" target), so the same bits: the x86-64
// baseline (SSE2, four lanes; the portable path, plain C++) and AVX2 (eight lanes), which takes
// about a third off the setup phase. simd_level() (SPLATKIT_SIMD) chooses.
template <bool kEllipse>
void setup_block(const FrameConstants& k, bool cull_backfaces, int count, Block& b) {
  setup_lanes<kEllipse, false>(k, cull_backfaces, count, b);
}

#if defined(__x86_64__)
template <bool kEllipse>
__attribute__((target("avx2"))) void setup_block_avx2(const FrameConstants& k, bool cull_backfaces,
                                                      int count, Block& b) {
  setup_lanes<kEllipse, true>(k, cull_backfaces, count, b);
}
#endif

template <bool kEllipse>
void setup_any(bool avx2, const FrameConstants& k, bool cull_backfaces, int count, Block& b) {
#if defined(__x86_64__)
  if (avx2) return setup_block_avx2<kEllipse>(k, cull_backfaces, count, b);
#endif
  setup_block<kEllipse>(k, cull_backfaces, count, b);
}

}  // namespace

std::size_t setup_splats(const DrawList& draws, const Projection& projection,
                         const SetupOptions& options, std::size_t begin, std::size_t end,
                         SplatRaster* out) {
  const FrameConstants k = frame_constants(projection);
  const bool avx2 = simd_level() >= SimdLevel::kAvx2;
  std::size_t drawn = 0;
  Block b;
  for (std::size_t first = begin; first < end; first += kBlock) {
    const int count = static_cast<int>(std::min<std::size_t>(kBlock, end - first));
    transpose_block(draws, k, first, count, b);
    if (draws.axes != nullptr)
      setup_any<true>(avx2, k, options.cull_backfaces, count, b);
    else
      setup_any<false>(avx2, k, options.cull_backfaces, count, b);
    for (int i = 0; i < count; ++i) {
      SplatRaster& s = out[first - begin + i];
      if (b.ok[i] == 0) {
        not_drawn(s);
        continue;
      }
      for (int j = 0; j < 3; ++j) {
        s.l[j] = b.l[j][i];
        s.u[j] = b.u[j][i];
        s.v[j] = b.v[j][i];
      }
      s.nc = b.nc[i];
      s.zmin = b.zmin[i];
      s.zmax = b.zmax[i];
      s.normal = draws.normals[first + i];
      s.cx = b.cx[i];
      s.cy = b.cy[i];
      s.ring2 = b.ring2[i];
      s.x0 = static_cast<int16_t>(b.x0[i]);
      s.x1 = static_cast<int16_t>(b.x1[i]);
      s.y0 = static_cast<int16_t>(b.y0[i]);
      s.y1 = static_cast<int16_t>(b.y1[i]);
      ++drawn;
    }
  }
  return drawn;
}

}  // namespace splatkit::render
