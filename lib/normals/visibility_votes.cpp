#include "normals/visibility_votes.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "normals/cover_splat.h"
#include "splatkit/simd_level.h"

namespace splatkit {

namespace {

constexpr float kMinFacing = 0.2f;  // views with |n·d| below this do not vote
constexpr float kMinSlope = 0.05f;  // |n·d| below this is drawn as this (a disc seen edge-on)
constexpr float kTolerance = 0.5f;  // × radius / |n·d|: depth tolerance of "seen"
constexpr float kVoteScale = 1024;  // |n·d| summed as integers in 1/1024
constexpr float kGrow = 0.75f;      // pixels added to every disc's radius when drawn
// Discs whose box of pixels is at most kBox × kBox (nearly all: a disc of the median radius
// spans 2.5 pixels) are drawn by the vector path as one whole box, the pixels off the disc masked
// out; the buffer has kBox − 1 spare columns and rows so that the box never leaves it.
constexpr std::size_t kBox = 4;
// Pixel size in median radii. Measured against 1 on the scan set (building, city, noisy city,
// CAD part, facade): the same orientations to within 0.2 %, the visibility pass faster.
constexpr float kPixel = 2.0f;

// std::lround(f * kVoteScale) for f in [0, 1], without the library call: the fraction of a
// float below 2^24 after its integer part is exact.
uint32_t vote_weight(float f) {
  const float x = f * kVoteScale;
  if (!(x < 1e6f)) return 0;  // NaN (std::lround's LONG_MIN, cast, is 0 as well)
  const auto whole = static_cast<int32_t>(x);
  return static_cast<uint32_t>(whole + (x - static_cast<float>(whole) >= 0.5f ? 1 : 0));
}

struct View {
  Vec3f d, u, w;  // towards the viewer, and the image's two axes
};

std::vector<View> view_directions(const VisibilityOptions& o) {
  const Vec3f up = normalized(o.up);
  const Vec3f e1 = tangent_axis(up), e2 = cross(up, e1);
  const double z0 = std::sin(o.min_elevation_deg * std::numbers::pi / 180);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  std::vector<View> views(o.views);
  for (std::size_t k = 0; k < o.views; ++k) {
    // Equal areas of the cap: z uniform in [z0, 1].
    const double z = 1 - (k + 0.5) / static_cast<double>(o.views) * (1 - z0);
    const double r = std::sqrt(std::max(0.0, 1 - z * z)), phi = golden * static_cast<double>(k);
    const Vec3f d =
        normalized(up * static_cast<float>(z) + e1 * static_cast<float>(r * std::cos(phi)) +
                   e2 * static_cast<float>(r * std::sin(phi)));
    const Vec3f u = tangent_axis(d);
    views[k] = {d, u, cross(d, u)};
  }
  return views;
}

// One view's depth buffer and the votes it adds.
struct ViewBuffer {
  std::vector<float> depth;           // rows of stride_ pixels
  std::vector<uint32_t> front, back;  // #N: sums of |n·d| from the normal's side and the other
};

class ViewDrawer {
 public:
  // Draws all of p, n, r; tests (votes for) the first `tested` only (the rest: occluders).
  ViewDrawer(std::span<const Vec3f> p, std::span<const Vec3f> n, std::span<const float> r,
             std::size_t tested, std::size_t max_pixels, bool sse2)
      : p_(p),
        n_(n),
        r_(r),
        tested_(tested),
        max_pixels_(std::max<std::size_t>(max_pixels, 1)),
        sse2_(sse2) {
    lo_ = hi_ = p[0];
    for (const Vec3f& q : p) {
      lo_ = {std::min(lo_.x, q.x), std::min(lo_.y, q.y), std::min(lo_.z, q.z)};
      hi_ = {std::max(hi_.x, q.x), std::max(hi_.y, q.y), std::max(hi_.z, q.z)};
    }
    std::vector<float> sorted(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(tested));
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    median_ = std::max(sorted[sorted.size() / 2], 1e-30f);
    max_radius_ = *std::max_element(r.begin(), r.end());
  }

  void operator()(const View& v, ViewBuffer& out) {
    frame(v);
    if (!usable_) return;
    out.depth.assign(stride_ * (height_ + kBox - 1), -std::numeric_limits<float>::infinity());
    std::size_t drawn = 0, tested = 0;  // points done four at a time
#if defined(__SSE2__)
    if (box_) {
      const ViewSse2 s(v, *this);
      for (; drawn + 4 <= p_.size(); drawn += 4) draw4_sse2(v, s, drawn, out.depth.data());
      for (; tested + 4 <= tested_; tested += 4) test4_sse2(s, tested, out);
    }
#endif
    for (std::size_t i = drawn; i < p_.size(); ++i) draw(v, i, out.depth.data());
    for (std::size_t i = tested; i < tested_; ++i) test(v, i, out);
  }

  float pixel() const { return h_; }

 private:
  // The image's extent: the bounding box's corners projected, grown by the largest radius.
  void frame(const View& v) {
    float a0 = std::numeric_limits<float>::max(), a1 = -a0, b0 = a0, b1 = -a0;
    for (int c = 0; c < 8; ++c) {
      const Vec3f q{c & 1 ? hi_.x : lo_.x, c & 2 ? hi_.y : lo_.y, c & 4 ? hi_.z : lo_.z};
      a0 = std::min(a0, dot(q, v.u)), a1 = std::max(a1, dot(q, v.u));
      b0 = std::min(b0, dot(q, v.w)), b1 = std::max(b1, dot(q, v.w));
    }
    const float grow = max_radius_ + median_;
    a0_ = a0 - grow, b0_ = b0 - grow;
    const float wa = a1 - a0 + 2 * grow, wb = b1 - b0 + 2 * grow;
    // Extents beyond float (a stray point near its limit): the view votes for nothing.
    usable_ = std::isfinite(wa * wb) && std::isfinite(a0_) && std::isfinite(b0_);
    if (!usable_) return;
    h_ = std::max(kPixel * median_, std::sqrt(wa * wb / static_cast<float>(max_pixels_)));
    width_ = static_cast<std::size_t>(wa / h_) + 1;
    height_ = static_cast<std::size_t>(wb / h_) + 1;
    while (width_ * height_ > max_pixels_) {  // rounding
      h_ *= 1.01f;
      width_ = static_cast<std::size_t>(wa / h_) + 1;
      height_ = static_cast<std::size_t>(wb / h_) + 1;
    }
    inv_h_ = 1 / h_;
    stride_ = width_ + kBox - 1;
    // The vector path takes pixel numbers as floats: exact below 2^24.
    box_ = sse2_ && std::max(width_, height_) + kBox < (std::size_t{1} << 24);
  }

  // The cell of image coordinate x in [0, size): clamped, NaN (an overflowed offset) to 0.
  std::size_t cell(float x, std::size_t size) const {
    const float c = x * inv_h_;
    if (!(c > 0)) return 0;
    // Through a signed conversion (one instruction on x86-64): here 0 < c < size − 1 < 2^63.
    return c >= static_cast<float>(size - 1) ? size - 1
                                             : static_cast<std::size_t>(static_cast<int64_t>(c));
  }
  std::size_t column(float a) const { return cell(a, width_); }
  std::size_t row(float b) const { return cell(b, height_); }

  // The disc's depth gradient in the image: its depth at the pixel centre (a + da, b + db) is
  // t − da·su − db·sw, on its plane whichever the normal's sign (edge-on discs as kMinSlope).
  static std::pair<float, float> depth_slopes(float nu, float nw, float nd) {
    const float slope = std::copysign(std::max(std::fabs(nd), kMinSlope), nd);
    return {nu / slope, nw / slope};
  }

  void draw(const View& v, std::size_t i, float* depth) const {
    const Vec3f& p = p_[i];
    const Vec3f& n = n_[i];
    const float a = dot(p, v.u) - a0_, b = dot(p, v.w) - b0_, t = dot(p, v.d);
    // Grown by 3/4 of a pixel: a disc then writes every pixel it overlaps, not only those whose
    // centre it holds, so that a surface's discs close the buffer where its splats do (a roof
    // over a ceiling, a wall over its inner face).
    const float nu = dot(n, v.u), nw = dot(n, v.w), nd = dot(n, v.d), r = r_[i] + kGrow * h_;
    // The disc's projection spans r·sqrt(1 − (n·u)²) along u (likewise w).
    const float ru = r * std::sqrt(std::max(0.0f, 1 - nu * nu));
    const float rw = r * std::sqrt(std::max(0.0f, 1 - nw * nw));
    const std::size_t x0 = column(a - ru), x1 = column(a + ru), cx = column(a);
    const std::size_t y0 = row(b - rw), y1 = row(b + rw), cy = row(b);
    // The pixel centres on the disc, row by row: at offset db from the centre the disc's
    // |offset in its plane|² = da² + db² + (da·nu + db·nw)² / slope² <= r² is a quadratic in da,
    // solved once per row; the depth is linear along the row.
    const auto [su, sw] = depth_slopes(nu, nw, nd);
    const float qa = 1 + su * su, to_x = inv_h_ / qa, a_x = a * inv_h_ - 0.5f;
    for (std::size_t y = y0; y <= y1; ++y) {
      const float db = (static_cast<float>(y) + 0.5f) * h_ - b;
      const float half_b = db * sw * su;
      const float c = db * db * (1 + sw * sw) - r * r;
      const float disc = half_b * half_b - qa * c;
      float* line = depth + y * stride_;
      if (disc >= 0) {
        const float root = std::sqrt(disc);
        // da in [(-half_b - root) / qa, (-half_b + root) / qa]; pixel x has da = (x + ½)h − a.
        const float lo = a_x - (half_b + root) * to_x, hi = a_x + (root - half_b) * to_x;
        const std::size_t from = std::max(x0, lo > 0 ? static_cast<std::size_t>(std::ceil(lo)) : 0);
        const float hi_c = std::min(hi, static_cast<float>(x1));
        if (hi_c >= 0) {
          const std::size_t to = static_cast<std::size_t>(hi_c);
          for (std::size_t x = from; x <= to; ++x) {
            const float da = (static_cast<float>(x) + 0.5f) * h_ - a;
            line[x] = std::max(line[x], t - da * su - db * sw);
          }
        }
      }
      if (y == cy) {  // the pixel holding the centre, on the disc or not
        const float da = (static_cast<float>(cx) + 0.5f) * h_ - a;
        line[cx] = std::max(line[cx], t - da * su - db * sw);
      }
    }
  }

#if defined(__SSE2__)
  // The view's constants in every lane.
  struct ViewSse2 {
    __m128 ux, uy, uz, wx, wy, wz, dx, dy, dz;
    __m128 a0, b0, h, inv_h, grow, last_column, last_row;
    ViewSse2(const View& v, const ViewDrawer& d)
        : ux(_mm_set1_ps(v.u.x)),
          uy(_mm_set1_ps(v.u.y)),
          uz(_mm_set1_ps(v.u.z)),
          wx(_mm_set1_ps(v.w.x)),
          wy(_mm_set1_ps(v.w.y)),
          wz(_mm_set1_ps(v.w.z)),
          dx(_mm_set1_ps(v.d.x)),
          dy(_mm_set1_ps(v.d.y)),
          dz(_mm_set1_ps(v.d.z)),
          a0(_mm_set1_ps(d.a0_)),
          b0(_mm_set1_ps(d.b0_)),
          h(_mm_set1_ps(d.h_)),
          inv_h(_mm_set1_ps(d.inv_h_)),
          grow(_mm_set1_ps(kGrow * d.h_)),
          last_column(_mm_set1_ps(static_cast<float>(d.width_ - 1))),
          last_row(_mm_set1_ps(static_cast<float>(d.height_ - 1))) {}
  };

  // Four points' x, y and z.
  struct Xyz4 {
    __m128 x, y, z;
  };
  static Xyz4 load4(std::span<const Vec3f> v, std::size_t i) {
    return {_mm_setr_ps(v[i].x, v[i + 1].x, v[i + 2].x, v[i + 3].x),
            _mm_setr_ps(v[i].y, v[i + 1].y, v[i + 2].y, v[i + 3].y),
            _mm_setr_ps(v[i].z, v[i + 1].z, v[i + 2].z, v[i + 3].z)};
  }
  // Vec3f's dot, in the same order.
  static __m128 dot4(const Xyz4& p, __m128 x, __m128 y, __m128 z) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(p.x, x), _mm_mul_ps(p.y, y)), _mm_mul_ps(p.z, z));
  }
  // cell: x · (1 / h) clamped to [0, last] (NaN to 0), truncated; as floats.
  static __m128 cell4(__m128 x, __m128 inv_h, __m128 last) {
    const __m128 c = _mm_min_ps(_mm_max_ps(_mm_mul_ps(x, inv_h), _mm_setzero_ps()), last);
    return _mm_cvtepi32_ps(_mm_cvttps_epi32(c));
  }
  // depth_slopes, by the same operations.
  static void depth_slopes4(__m128 nu, __m128 nw, __m128 nd, __m128& su, __m128& sw) {
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 slope = _mm_or_ps(_mm_and_ps(nd, sign),
                                   _mm_max_ps(_mm_set1_ps(kMinSlope), _mm_andnot_ps(sign, nd)));
    su = _mm_div_ps(nu, slope);
    sw = _mm_div_ps(nw, slope);
  }

  // draw's disc.
  struct Disc {
    float a, b, t, r, su, sw, qa, to_x, a_x;
  };

  // draw for points i .. i + 3, the same depths: their discs' projections four at a time, then
  // each disc whose pixels fit a kBox × kBox box by draw_box_sse2, the others by draw.
  void draw4_sse2(const View& v, const ViewSse2& s, std::size_t i, float* depth) const {
    const Xyz4 p = load4(p_, i), n = load4(n_, i);
    const __m128 a = _mm_sub_ps(dot4(p, s.ux, s.uy, s.uz), s.a0);
    const __m128 b = _mm_sub_ps(dot4(p, s.wx, s.wy, s.wz), s.b0);
    const __m128 t = dot4(p, s.dx, s.dy, s.dz);
    const __m128 nu = dot4(n, s.ux, s.uy, s.uz), nw = dot4(n, s.wx, s.wy, s.wz);
    const __m128 nd = dot4(n, s.dx, s.dy, s.dz);
    const __m128 r = _mm_add_ps(_mm_loadu_ps(r_.data() + i), s.grow);
    // std::max(0.0f, x) is 0 for a NaN x; _mm_max_ps(x, 0) likewise.
    const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
    const __m128 ru =
        _mm_mul_ps(r, _mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(one, _mm_mul_ps(nu, nu)), zero)));
    const __m128 rw =
        _mm_mul_ps(r, _mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(one, _mm_mul_ps(nw, nw)), zero)));
    const __m128 x0 = cell4(_mm_sub_ps(a, ru), s.inv_h, s.last_column);
    const __m128 x1 = cell4(_mm_add_ps(a, ru), s.inv_h, s.last_column);
    const __m128 y0 = cell4(_mm_sub_ps(b, rw), s.inv_h, s.last_row);
    const __m128 y1 = cell4(_mm_add_ps(b, rw), s.inv_h, s.last_row);
    __m128 su, sw;
    depth_slopes4(nu, nw, nd, su, sw);
    const __m128 qa = _mm_add_ps(one, _mm_mul_ps(su, su));
    const __m128 box = _mm_set1_ps(static_cast<float>(kBox));
    // x1 - x0 < kBox as draw's size_t difference says it (x1 < x0 only for a negative radius).
    const __m128 small_x = _mm_and_ps(_mm_cmple_ps(x0, x1), _mm_cmplt_ps(_mm_sub_ps(x1, x0), box));
    const __m128 small_y = _mm_and_ps(_mm_cmple_ps(y0, y1), _mm_cmplt_ps(_mm_sub_ps(y1, y0), box));
    const int small = _mm_movemask_ps(_mm_and_ps(small_x, small_y));
    alignas(16) float lane[9][4];
    _mm_store_ps(lane[0], a), _mm_store_ps(lane[1], b), _mm_store_ps(lane[2], t);
    _mm_store_ps(lane[3], r), _mm_store_ps(lane[4], su), _mm_store_ps(lane[5], sw);
    _mm_store_ps(lane[6], qa), _mm_store_ps(lane[7], _mm_div_ps(s.inv_h, qa));
    _mm_store_ps(lane[8], _mm_sub_ps(_mm_mul_ps(a, s.inv_h), _mm_set1_ps(0.5f)));
    alignas(16) int32_t cells[6][4];
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[0]), _mm_cvttps_epi32(x0));
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[1]), _mm_cvttps_epi32(x1));
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[2]),
                    _mm_cvttps_epi32(cell4(a, s.inv_h, s.last_column)));
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[3]), _mm_cvttps_epi32(y0));
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[4]), _mm_cvttps_epi32(y1));
    _mm_store_si128(reinterpret_cast<__m128i*>(cells[5]),
                    _mm_cvttps_epi32(cell4(b, s.inv_h, s.last_row)));
    for (int k = 0; k < 4; ++k) {
      if (!(small >> k & 1)) {
        draw(v, i + static_cast<std::size_t>(k), depth);
        continue;
      }
      const Disc d{lane[0][k], lane[1][k], lane[2][k], lane[3][k], lane[4][k],
                   lane[5][k], lane[6][k], lane[7][k], lane[8][k]};
      auto at = [&](int c) { return static_cast<std::size_t>(cells[c][k]); };
      draw_box_sse2(d, at(0), at(1), at(2), at(3), at(4), at(5), depth);
    }
  }

  // draw's rows four at a time: the pixels of the kBox × kBox box from (x0, y0) that draw's row
  // spans or its centre pixel write (x in [x0, x1], y in [y0, y1]) get the same depths, by the
  // same float operations; the others keep theirs. A span [from, to] is the pixels x with
  // x >= lo (not x < lo: a NaN lo starts at x0, as draw's does) and x <= hi.
  void draw_box_sse2(const Disc& d, std::size_t x0, std::size_t x1, std::size_t cx, std::size_t y0,
                     std::size_t y1, std::size_t cy, float* depth) const {
    const __m128 ramp = _mm_setr_ps(0, 1, 2, 3), half = _mm_set1_ps(0.5f), h = _mm_set1_ps(h_);
    const __m128 su = _mm_set1_ps(d.su), sw = _mm_set1_ps(d.sw);
    // Per row (lanes: y0 .. y0 + 3).
    const __m128 y = _mm_add_ps(_mm_set1_ps(static_cast<float>(y0)), ramp);
    const __m128 db = _mm_sub_ps(_mm_mul_ps(_mm_add_ps(y, half), h), _mm_set1_ps(d.b));
    const __m128 half_b = _mm_mul_ps(_mm_mul_ps(db, sw), su);
    const __m128 c = _mm_sub_ps(_mm_mul_ps(_mm_mul_ps(db, db), _mm_set1_ps(1 + d.sw * d.sw)),
                                _mm_set1_ps(d.r * d.r));
    const __m128 disc = _mm_sub_ps(_mm_mul_ps(half_b, half_b), _mm_mul_ps(_mm_set1_ps(d.qa), c));
    const __m128 span = _mm_and_ps(_mm_cmpge_ps(disc, _mm_setzero_ps()),
                                   _mm_cmple_ps(y, _mm_set1_ps(static_cast<float>(y1))));
    const __m128 root = _mm_sqrt_ps(_mm_and_ps(span, disc));  // 0 off the spans
    const __m128 to_x = _mm_set1_ps(d.to_x), a_x = _mm_set1_ps(d.a_x);
    const __m128 lo = _mm_sub_ps(a_x, _mm_mul_ps(_mm_add_ps(half_b, root), to_x));
    const __m128 hi = _mm_add_ps(a_x, _mm_mul_ps(_mm_sub_ps(root, half_b), to_x));
    const __m128 dz = _mm_mul_ps(db, sw);
    const __m128 centre_row = _mm_cmpeq_ps(y, _mm_set1_ps(static_cast<float>(cy)));
    // Per column (lanes: x0 .. x0 + 3).
    const __m128 x = _mm_add_ps(_mm_set1_ps(static_cast<float>(x0)), ramp);
    const __m128 in_box = _mm_cmple_ps(x, _mm_set1_ps(static_cast<float>(x1)));
    const __m128 centre_column = _mm_cmpeq_ps(x, _mm_set1_ps(static_cast<float>(cx)));
    const __m128 da = _mm_sub_ps(_mm_mul_ps(_mm_add_ps(x, half), h), _mm_set1_ps(d.a));
    const __m128 z_row = _mm_sub_ps(_mm_set1_ps(d.t), _mm_mul_ps(da, su));  // t − da·su
    // Row k (a compile-time lane number) of the box.
    auto row = [&](auto k) {
      constexpr int lane = decltype(k)::value * 0x55;  // lane k in every lane
      const __m128 on =
          _mm_or_ps(_mm_and_ps(_mm_and_ps(_mm_shuffle_ps(span, span, lane), in_box),
                               _mm_and_ps(_mm_cmpnlt_ps(x, _mm_shuffle_ps(lo, lo, lane)),
                                          _mm_cmple_ps(x, _mm_shuffle_ps(hi, hi, lane)))),
                    _mm_and_ps(_mm_shuffle_ps(centre_row, centre_row, lane), centre_column));
      float* line = depth + (y0 + decltype(k)::value) * stride_ + x0;
      const __m128 old = _mm_loadu_ps(line);
      // std::max(old, z) is old unless old < z; _mm_max_ps(z, old) likewise (also for NaNs).
      const __m128 z = _mm_sub_ps(z_row, _mm_shuffle_ps(dz, dz, lane));
      const __m128 drawn = _mm_max_ps(z, old);
      _mm_storeu_ps(line, _mm_or_ps(_mm_and_ps(on, drawn), _mm_andnot_ps(on, old)));
    };
    row(std::integral_constant<int, 0>{});
    row(std::integral_constant<int, 1>{});
    row(std::integral_constant<int, 2>{});
    row(std::integral_constant<int, 3>{});
  }

  // test for points i .. i + 3, the same votes.
  void test4_sse2(const ViewSse2& s, std::size_t i, ViewBuffer& out) const {
    const Xyz4 p = load4(p_, i), n = load4(n_, i);
    const __m128 nd = dot4(n, s.dx, s.dy, s.dz);
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 facing = _mm_andnot_ps(sign, nd);  // |n·d|
    const __m128 a = _mm_sub_ps(dot4(p, s.ux, s.uy, s.uz), s.a0);
    const __m128 b = _mm_sub_ps(dot4(p, s.wx, s.wy, s.wz), s.b0);
    const __m128 t = dot4(p, s.dx, s.dy, s.dz);
    const __m128 x = cell4(a, s.inv_h, s.last_column), y = cell4(b, s.inv_h, s.last_row);
    const __m128 half = _mm_set1_ps(0.5f);
    const __m128 da = _mm_sub_ps(_mm_mul_ps(_mm_add_ps(x, half), s.h), a);
    const __m128 db = _mm_sub_ps(_mm_mul_ps(_mm_add_ps(y, half), s.h), b);
    __m128 su, sw;
    depth_slopes4(dot4(n, s.ux, s.uy, s.uz), dot4(n, s.wx, s.wy, s.wz), nd, su, sw);
    const __m128 own = _mm_sub_ps(_mm_sub_ps(t, _mm_mul_ps(da, su)), _mm_mul_ps(db, sw));
    // std::min(x, 1.0f) is 1 unless x <= 1 or NaN; _mm_min_ps(1, x) likewise.
    const __m128 tolerance =
        _mm_mul_ps(_mm_min_ps(_mm_set1_ps(1.0f), _mm_div_ps(_mm_set1_ps(kTolerance), facing)),
                   _mm_loadu_ps(r_.data() + i));
    alignas(16) int32_t xs[4], ys[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(xs), _mm_cvttps_epi32(x));
    _mm_store_si128(reinterpret_cast<__m128i*>(ys), _mm_cvttps_epi32(y));
    auto pixel = [&](int k) {
      return out.depth[static_cast<std::size_t>(ys[k]) * stride_ + static_cast<std::size_t>(xs[k])];
    };
    const __m128 buffer = _mm_setr_ps(pixel(0), pixel(1), pixel(2), pixel(3));
    int seen = _mm_movemask_ps(_mm_and_ps(_mm_cmpnlt_ps(facing, _mm_set1_ps(kMinFacing)),
                                          _mm_cmpnlt_ps(own, _mm_sub_ps(buffer, tolerance))));
    if (seen == 0) return;
    alignas(16) float nds[4];
    _mm_store_ps(nds, nd);
    for (; seen != 0; seen &= seen - 1) {
      const int k = std::countr_zero(static_cast<unsigned>(seen));
      (nds[k] > 0 ? out.front : out.back)[i + static_cast<std::size_t>(k)] +=
          vote_weight(std::fabs(nds[k]));
    }
  }
#endif

  void test(const View& v, std::size_t i, ViewBuffer& out) const {
    const Vec3f& p = p_[i];
    const Vec3f& n = n_[i];
    const float nd = dot(n, v.d);
    if (std::fabs(nd) < kMinFacing) return;
    const float a = dot(p, v.u) - a0_, b = dot(p, v.w) - b0_, t = dot(p, v.d);
    const std::size_t x = column(a), y = row(b);
    const float da = (static_cast<float>(x) + 0.5f) * h_ - a;
    const float db = (static_cast<float>(y) + 0.5f) * h_ - b;
    const auto [su, sw] = depth_slopes(dot(n, v.u), dot(n, v.w), nd);
    const float own = t - da * su - db * sw;
    const float tolerance = std::min(kTolerance / std::fabs(nd), 1.0f) * r_[i];
    if (own < out.depth[y * stride_ + x] - tolerance) return;
    const auto q = vote_weight(std::fabs(nd));
    (nd > 0 ? out.front : out.back)[i] += q;
  }

  std::span<const Vec3f> p_, n_;
  std::span<const float> r_;
  std::size_t tested_;
  std::size_t max_pixels_;
  bool sse2_;
  Vec3f lo_, hi_;
  float median_ = 0, max_radius_ = 0;
  float a0_ = 0, b0_ = 0, h_ = 0, inv_h_ = 0;
  bool usable_ = true;
  bool box_ = false;  // draw the small discs by draw_box_sse2
  std::size_t width_ = 0, height_ = 0, stride_ = 0;
};

// The discs that stand for the walls: per wall a grid of discs whose radius is the grid's step
// (neighbouring discs overlap: no gap between them), by default at most kWallDiscs on a side.
constexpr int kWallDiscs = 64;

void add_wall_discs(const std::vector<VisibilityWall>& walls, std::vector<Vec3f>& p,
                    std::vector<Vec3f>& n, std::vector<float>& r) {
  for (const VisibilityWall& w : walls) {
    const float length = norm(w.along);
    const float height = w.top - w.base.z;
    if (!(length > 0) || !(height > 0)) continue;
    const float step = w.step > 0 ? w.step : std::max(length, height) / kWallDiscs;
    const int across = static_cast<int>(std::ceil(length / step)),
              up = static_cast<int>(std::ceil(height / step));
    const Vec3f u = w.along * (1.0f / length);
    const Vec3f normal{-u.y, u.x, 0};
    for (int a = 0; a <= across; ++a)
      for (int b = 0; b <= up; ++b) {
        p.push_back(w.base + u * std::min(length, a * step) +
                    Vec3f{0, 0, std::min(height, b * step)});
        n.push_back(normal);
        r.push_back(step);
      }
  }
}

}  // namespace

std::vector<float> visibility_votes(std::span<const Vec3f> positions,
                                    std::span<const Vec3f> normals, std::span<const float> radii,
                                    const VisibilityOptions& options, VisibilityStats* stats) {
  const std::size_t n = positions.size();
  if (n == 0 || options.views == 0) return std::vector<float>(n, 0.0f);
  const std::vector<View> views = view_directions(options);
  // With walls, the splats and the walls' discs drawn together (only the splats vote).
  std::vector<Vec3f> all_p, all_n;
  std::vector<float> all_r;
  if (!options.walls.empty()) {
    all_p.assign(positions.begin(), positions.end());
    all_n.assign(normals.begin(), normals.end());
    all_r.assign(radii.begin(), radii.end());
    add_wall_discs(options.walls, all_p, all_n, all_r);
    positions = all_p, normals = all_n, radii = all_r;
  }
  const ViewDrawer prototype(positions, normals, radii, n, options.max_pixels,
                             simd_level() >= SimdLevel::kSse2);
  tbb::enumerable_thread_specific<ViewBuffer> buffers([&] {
    ViewBuffer b;
    b.front.assign(n, 0);
    b.back.assign(n, 0);
    return b;
  });
  tbb::enumerable_thread_specific<ViewDrawer> drawers(prototype);
  float pixel = 0;
  tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t k) {
    ViewDrawer& drawer = drawers.local();
    drawer(views[k], buffers.local());
    if (k == 0) pixel = drawer.pixel();
  });
  std::vector<uint32_t> front(n, 0), back(n, 0);
  for (const ViewBuffer& b : buffers)
    for (std::size_t i = 0; i < n; ++i) front[i] += b.front[i], back[i] += b.back[i];
  std::vector<float> votes(n, 0.0f);
  std::size_t seen = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = front[i], b = back[i];
    if (f + b == 0) continue;
    votes[i] = static_cast<float>((f - b) / (f + b));
    ++seen;
  }
  if (stats) *stats = {seen, pixel};
  return votes;
}

}  // namespace splatkit
