#include "normals/cover_splat.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

namespace splatkit {

namespace {

// tan(60°): neighbours more than 60° above or below the tangent plane do not bound the cell.
constexpr double kSheetSlope = 1.7320508075688772;
// An open cell whose vertices on the square point, on average, at least this much to one side
// (the mean of their unit directions) opens outwards only: a border point (Cell::open_side).
constexpr double kBorderSide = 0.5;

struct P2 {
  double x, y;
};

// The cell as a convex polygon, counter-clockwise, clipped in place by half-planes. Fixed
// capacity, on the stack: a clip that would need more vertices is skipped, which leaves the cell
// larger than it is (the splat still covers it). Voronoi cells have about 6 vertices.
class Cell {
 public:
  static constexpr std::size_t kCapacity = 64;

  explicit Cell(double half) {
    v_[0] = {-half, -half};
    v_[1] = {half, -half};
    v_[2] = {half, half};
    v_[3] = {-half, half};
    n_ = 4;
    max_sq_ = 2 * half * half;
  }

  // Keeps {x : d·x <= share · |d|²}: share 1/2, the side of the bisector of the centre (the
  // origin) and d; share 1, the side of the line through d.
  void clip(const P2& d, double share = 0.5) {
    const double d_sq = d.x * d.x + d.y * d.y;
    const double limit = share * d_sq;
    // The whole cell is on the centre's side when its farthest vertex R is: R |d| <= limit.
    if (max_sq_ * d_sq <= limit * limit) return;
    double side[kCapacity];
    bool cut = false;
    for (std::size_t i = 0; i < n_; ++i) {
      side[i] = d.x * v_[i].x + d.y * v_[i].y - limit;
      cut |= side[i] > 0;
    }
    if (!cut || n_ + 1 > kCapacity) return;
    std::size_t m = 0;
    double max_sq = 0;
    auto keep = [&](const P2& q) {
      out_[m++] = q;
      max_sq = std::max(max_sq, q.x * q.x + q.y * q.y);
    };
    std::size_t a = n_ - 1;
    for (std::size_t b = 0; b < n_; a = b++) {
      if ((side[a] < 0 && side[b] > 0) || (side[a] > 0 && side[b] < 0)) {
        const double t = side[a] / (side[a] - side[b]);
        keep({v_[a].x + t * (v_[b].x - v_[a].x), v_[a].y + t * (v_[b].y - v_[a].y)});
      }
      if (side[b] <= 0) keep(v_[b]);
    }
    std::swap(v_, out_);
    n_ = m;
    max_sq_ = max_sq;
  }

  std::span<const P2> vertices() const { return {v_, n_}; }
  // Whether a vertex lies on the starting square: the neighbours leave the cell open that way.
  static bool on_square(const P2& p, double half) {
    const double edge = half * (1 - 1e-9);
    return std::fabs(p.x) >= edge || std::fabs(p.y) >= edge;
  }
  bool open(double half) const {
    for (const P2& p : vertices())
      if (on_square(p, half)) return true;
    return false;
  }
  // For an open cell: the mean of the unit directions of its vertices on the square. Long (at
  // least kBorderSide) when the cell opens to one side only: the border of an open surface, not a
  // thread open on both sides.
  P2 open_side(double half) const {
    double sx = 0, sy = 0;
    std::size_t on = 0;
    for (const P2& p : vertices())
      if (on_square(p, half)) {
        const double len = std::hypot(p.x, p.y);
        sx += p.x / len, sy += p.y / len;
        ++on;
      }
    return on ? P2{sx / static_cast<double>(on), sy / static_cast<double>(on)} : P2{0, 0};
  }
  double max_sq() const { return max_sq_; }

  // Second moment of area about the origin, ∫ x xᵀ dA = [xx xy; xy yy], as a fan of triangles
  // (origin, v_i, v_i+1); the origin lies inside the cell.
  std::array<double, 3> second_moment() const {
    std::array<double, 3> m{0, 0, 0};
    for (std::size_t i = 0; i < n_; ++i) {
      const P2& p = v_[i];
      const P2& q = v_[(i + 1) % n_];
      const double w = (p.x * q.y - p.y * q.x) / 12.0;  // (area / 6), area = cross / 2
      m[0] += w * (p.x * p.x + q.x * q.x + p.x * q.x);
      m[1] += w * (p.x * p.y + q.x * q.y + 0.5 * (p.x * q.y + q.x * p.y));
      m[2] += w * (p.y * p.y + q.y * q.y + p.y * q.y);
    }
    return m;
  }

 private:
  P2 buffers_[2][kCapacity];
  P2* v_ = buffers_[0];    // the cell's vertices
  P2* out_ = buffers_[1];  // where a clip writes the next ones
  std::size_t n_ = 0;
  double max_sq_ = 0;
};

}  // namespace

Vec3f tangent_axis(const Vec3f& n) {
  const float sign = n.z >= 0 ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z);
  return {1.0f + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x};
}

SplatShape cover_splat(const Vec3f& center, const Vec3f& normal, std::span<const Vec3f> positions,
                       std::span<const uint32_t> row, float open_cap, bool ellipse,
                       std::span<const Vec3f> normals) {
  const Vec3f t1 = tangent_axis(normal);
  const Vec3f t2 = cross(normal, t1);
  // The square reaches the farthest neighbour: every bounded cell fits inside.
  double half = 0;
  for (uint32_t j : row)
    if (j < positions.size()) half = std::max(half, double(squared_distance(positions[j], center)));
  half = std::max(std::sqrt(half), double(open_cap));
  Cell cell(half);
  // Projections shorter than this would make a bisector through the centre: skipped.
  const double tiny_sq = 1e-12 * half * half;
  for (uint32_t j : row) {
    if (j >= positions.size()) continue;  // kNone
    const Vec3f d = positions[j] - center;
    const P2 p{dot(d, t1), dot(d, t2)};
    const double along = dot(d, normal), in_plane_sq = p.x * p.x + p.y * p.y;
    if (in_plane_sq <= tiny_sq) continue;
    // Steeper than kSheetSlope above or below the plane: another sheet of the surface (across a
    // crease, the far side of a thin part), whose own splats cover what lies near it.
    if (along * along > kSheetSlope * kSheetSlope * in_plane_sq) continue;
    // A neighbour on another sheet by its normal (across a crease) bounds the cell at its own
    // projection, not half-way: this sheet's splats reach the crease, up to where the other
    // sheet's samples begin.
    const bool other = !normals.empty() && std::fabs(dot(normals[j], normal)) < kSameSheetCos;
    cell.clip(p, other ? 1.0 : 0.5);
  }
  SplatShape s;
  s.axis = t1;
  // An open cell is cut at open_cap; a closed one is covered whole. On the border of an open
  // surface the cell opens outwards only, and is first cut a little past the point on that side:
  // the splat covers the cell inwards and along the border, not open_cap past the border.
  s.open = cell.open(half);
  const double cap = s.open ? double(open_cap) : half;
  if (s.open) {
    const P2 side = cell.open_side(half);
    const double len = std::hypot(side.x, side.y);
    if (len >= kBorderSide) {
      // The surface ends about half a spacing (open_cap / 4: half the mean kNN distance) past
      // its border samples: the cell is cut there, across the side it opens to.
      const double margin = 2.0 * double(open_cap) / 4.0 / len;  // (the bisector halves it)
      cell.clip({side.x * margin, side.y * margin}, 0.5);
    }
  }
  const double reach = std::min(std::sqrt(cell.max_sq()), cap);
  s.radius = s.minor_radius = static_cast<float>(reach);
  // An open cell is cut at the cap in every direction: only a circle still covers all of it
  // within the cap (an ellipse shortened to the cap would lose corners nearer than the cap).
  if (!ellipse || s.open) return s;

  const std::array<double, 3> m = cell.second_moment();
  const double mean = 0.5 * (m[0] + m[2]), dev = std::hypot(0.5 * (m[0] - m[2]), m[1]);
  const double lmax = mean + dev, lmin = mean - dev;
  if (!(lmax > 0)) return s;
  const double angle = 0.5 * std::atan2(2 * m[1], m[0] - m[2]);
  const P2 e1{std::cos(angle), std::sin(angle)}, e2{-e1.y, e1.x};
  const double aspect = std::max(std::sqrt(std::max(lmin, 0.0) / lmax), 1.0 / kMaxEllipseAspect);
  double scale_sq = 0;  // smallest scale of the (1, aspect) ellipse that holds every vertex
  for (const P2& v : cell.vertices()) {
    const double u = v.x * e1.x + v.y * e1.y, w = (v.x * e2.x + v.y * e2.y) / aspect;
    scale_sq = std::max(scale_sq, u * u + w * w);
  }
  const double major = std::min(std::sqrt(scale_sq), cap);
  const double minor = std::min(std::sqrt(scale_sq) * aspect, major);
  if (!(major * minor < reach * reach)) return s;  // the circle is no larger
  s.radius = static_cast<float>(major);
  s.minor_radius = static_cast<float>(minor);
  s.axis = normalized(t1 * static_cast<float>(e1.x) + t2 * static_cast<float>(e1.y));
  return s;
}

}  // namespace splatkit
