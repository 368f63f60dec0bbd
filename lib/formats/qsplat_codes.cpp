#include "formats/qsplat_codes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace splatkit::qsplat {

namespace {

constexpr int kN = 13;

struct SphereTables {
  std::array<SphereCell, kSphereCells> cells{};
  // [size − 1 + 13·(x + 13·(y + 13·z))] -> S, or -1 for a cell outside the table.
  std::array<int16_t, kN * kN * kN * kN> index{};
  // 1 − (|(X, Y, Z)| + R) of each cell, in double: how far inside a unit parent it lies.
  std::array<double, kSphereCells> inside{};
};

const SphereTables& sphere_tables() {
  static const SphereTables t = [] {
    SphereTables s;
    s.index.fill(-1);
    const float one_nth = 1.0f / static_cast<float>(kN);
    const float sqrt3 = std::sqrt(3.0f);
    int i = 0;
    for (int size = 1; size <= kN; ++size)
      for (int x = 0; x < kN + 1 - size; ++x)
        for (int y = 0; y < kN + 1 - size; ++y)
          for (int z = 0; z < kN + 1 - size; ++z) {
            // Float arithmetic in the original's order: the decoded values must match its viewer.
            const float X = static_cast<float>(size + 2 * x) * one_nth - 1.0f;
            const float Y = static_cast<float>(size + 2 * y) * one_nth - 1.0f;
            const float Z = static_cast<float>(size + 2 * z) * one_nth - 1.0f;
            const float R = static_cast<float>(size) * one_nth;
            const float lim = 1.0f + sqrt3 * R;
            if (X * X + Y * Y + Z * Z > lim * lim) continue;
            s.cells[i] = {X, Y, Z, R};
            s.inside[i] = 1.0 - (std::sqrt(double{X} * X + double{Y} * Y + double{Z} * Z) + R);
            s.index[size - 1 + kN * (x + kN * (y + kN * z))] = static_cast<int16_t>(i);
            ++i;
          }
    return s;
  }();
  return t;
}

float unwarp_exact(unsigned k) {
  const float t = (static_cast<float>(k) + 0.5f) * (2.0f / static_cast<float>(kNormalSteps)) - 1.0f;
  return std::min(std::max(static_cast<float>(std::tan(t * M_PI * 0.25f)), -1.0f), 1.0f);
}

// The decoded value of step k of a stored component (the original's UNWARP), tabulated.
float unwarp(unsigned k) {
  static const std::array<float, kNormalSteps> t = [] {
    std::array<float, kNormalSteps> a{};
    for (unsigned i = 0; i < kNormalSteps; ++i) a[i] = unwarp_exact(i);
    return a;
  }();
  return t[k];
}

std::array<Vec3f, kNormalCodes> make_normal_table() {
  std::array<Vec3f, kNormalCodes> t{};
  for (int a = 0; a < 6; ++a) {
    const int axis = a / 2;  // 0: x (u = y, v = z), 1: y (u = z, v = x), 2: z (u = x, v = y)
    const float sign = (a & 1) ? -1.0f : 1.0f;
    for (unsigned u = 0; u < kNormalSteps; ++u)
      for (unsigned v = 0; v < kNormalSteps; ++v) {
        const float fu = unwarp(u), fv = unwarp(v);
        const float rest = 1.0f - fu * fu - fv * fv;
        Vec3f n;
        n[(axis + 1) % 3] = fu;
        n[(axis + 2) % 3] = fv;
        n[axis] = sign * std::sqrt(std::max(rest, 0.0f));
        if (rest < 0) n = normalized(n);
        t[(a * kNormalSteps + u) * kNormalSteps + v] = n;
      }
  }
  return t;
}

const std::array<Vec3f, kNormalCodes>& normal_table() {
  static const std::array<Vec3f, kNormalCodes> t = make_normal_table();
  return t;
}

// The decoded normals again, one array per component, for encode_normal's candidates, each face's
// 52 × 52 codes framed by a border of one row and one column on every side: entry
// (a, u + 1, v + 1) of a face of 54 × 54 holds code (a, u, v). The border, and a code whose two
// stored components lie outside the unit circle (the original's table holds no unit normal
// there, and the encoder writes no such code), hold NaN, which is never closer than anything: the
// 3 × 3 candidates around any code are read without bounds checks.
constexpr int kFramed = kNormalSteps + 2;

struct NormalComponents {
  std::array<float, 6 * kFramed * kFramed> x, y, z;
  // Per code (framed index): a normal whose dot product with the code's normal exceeds this is
  // closer to it than to any of its 3 × 3 neighbours, by far more than float rounding (2: never,
  // for a code outside the unit circle). With δ the least angle from the code to a neighbour,
  // a normal within δ/2 of the code lies more than δ/2 from every neighbour (triangle
  // inequality); the bound is cos(δ/2) + 1e-5, a margin that keeps the neighbours' dot products
  // at least about 2e-5 below the code's, some hundred times the error of a float dot product.
  std::array<float, 6 * kFramed * kFramed> own_wins;
};

const NormalComponents& normal_components() {
  static const NormalComponents c = [] {
    NormalComponents t{};
    t.x.fill(std::numeric_limits<float>::quiet_NaN());
    t.y.fill(std::numeric_limits<float>::quiet_NaN());
    t.z.fill(std::numeric_limits<float>::quiet_NaN());
    const std::array<Vec3f, kNormalCodes>& n = normal_table();
    for (int q = 0; q < kNormalCodes; ++q) {
      const int a = q / (kNormalSteps * kNormalSteps), u = q / kNormalSteps % kNormalSteps,
                v = q % kNormalSteps;
      const float fu = unwarp(static_cast<unsigned>(u)), fv = unwarp(static_cast<unsigned>(v));
      if (fu * fu + fv * fv > 1.0f) continue;
      const int at = (a * kFramed + u + 1) * kFramed + v + 1;
      t.x[at] = n[q].x;
      t.y[at] = n[q].y;
      t.z[at] = n[q].z;
    }
    t.own_wins.fill(2.0f);
    for (int at = 0; at < 6 * kFramed * kFramed; ++at) {
      if (std::isnan(t.x[at])) continue;  // the frame, or a code outside the unit circle
      double least = M_PI;
      for (int du = -1; du <= 1; ++du)
        for (int dv = -1; dv <= 1; ++dv) {
          const int j = at + du * kFramed + dv;
          if ((du == 0 && dv == 0) || std::isnan(t.x[j])) continue;
          const double cj =
              double{t.x[at]} * t.x[j] + double{t.y[at]} * t.y[j] + double{t.z[at]} * t.z[j];
          least = std::min(least, std::acos(std::clamp(cj, -1.0, 1.0)));
        }
      const double bound = std::cos(least / 2) + 1e-5;
      float f = static_cast<float>(bound);
      if (f < bound) f = std::nextafter(f, 2.0f);
      t.own_wins[at] = std::min(f, 2.0f);
    }
    return t;
  }();
  return c;
}

// The original's step of a component c: k = int((w + 1) / 2 · 52) with w = atan(c) · 4/π
// clamped to [−1, 1], i.e. the number of steps k >= 1 with c >= tan((k / 26 − 1) · π/4): counted
// against those 51 bounds, without an atan per component.
int warp_index(float c) {
  constexpr int kBounds = kNormalSteps - 1, kBuckets = 256;
  struct Table {
    std::array<float, kBounds> bounds;
    std::array<uint8_t, kBuckets> start;  // the count of bounds below each bucket's lower end
  };
  static const Table t = [] {
    Table w{};
    for (int k = 1; k < kNormalSteps; ++k)
      w.bounds[k - 1] = static_cast<float>(std::tan((2.0 * k / kNormalSteps - 1.0) * M_PI / 4));
    for (int b = 0; b < kBuckets; ++b) {
      const float lower = static_cast<float>(b) * (2.0f / kBuckets) - 1.0f;
      w.start[b] = static_cast<uint8_t>(std::lower_bound(w.bounds.begin(), w.bounds.end(), lower) -
                                        w.bounds.begin());
    }
    return w;
  }();
  // Bounds stand at least 0.03 apart, buckets 2/256 wide: the bucket's count is within one of
  // the answer, and one step down or up makes it exact whatever rounding put c in that bucket.
  const float at = (c + 1.0f) * (kBuckets / 2);
  const int b = at >= 0 ? (at < kBuckets ? static_cast<int>(at) : kBuckets - 1) : 0;
  int k = t.start[b];
  k -= k > 0 && t.bounds[k - 1] > c;
  k += k < kBounds && t.bounds[k] <= c;
  return k;
}

// std::floor and std::ceil of a value well inside the int range, as ints: the same results
// without the library's general case (the rounding instructions are not in the x86-64 baseline,
// and these bounds are computed several times per node).
int floor_int(double v) {
  const int i = static_cast<int>(v);
  return i - (v < i ? 1 : 0);
}
int ceil_int(double v) {
  const int i = static_cast<int>(v);
  return i + (v > i ? 1 : 0);
}

double distance(const Vec3f& a, const double b[3]) {
  const double dx = double{a.x} - b[0], dy = double{a.y} - b[1], dz = double{a.z} - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

const std::array<SphereCell, kSphereCells>& sphere_cells() { return sphere_tables().cells; }

namespace {

// size / 13 for size 0..13: the radius of a cell of that size in parent radii.
constexpr std::array<double, kN + 1> kCellRadius = [] {
  std::array<double, kN + 1> r{};
  for (int size = 0; size <= kN; ++size) r[size] = static_cast<double>(size) / kN;
  return r;
}();

// What one cell offers a child: the cell is not (or cannot be proved) inside the parent, it is
// too small or too far to contain the child, or it fits at distance `dist` between the centres.
enum class Offer { kNotInParent, kTooSmall, kFits };

}  // namespace

SphereEncoder::SphereEncoder(const Sphere& parent)
    : parent_(parent), pc_{parent.centre.x, parent.centre.y, parent.centre.z}, pr_(parent.radius) {
  // The decoded child is computed in float from the parent's float centre: its distance to the
  // parent's centre may be off by a few units in the last place of the coordinates. A cell more
  // than that (in parent radii) inside or outside the unit sphere needs no exact check.
  const double far = std::max({std::fabs(pc_[0]), std::fabs(pc_[1]), std::fabs(pc_[2])}) + pr_;
  unsure_ = 8.0 * far * 0x1p-23 / pr_ + 1e-9;
  // The same bound in steps of the cell grid (2/13 parent radii): how far a decoded cell centre
  // may stand from where exact arithmetic puts it, along one axis.
  unsure_steps_ = unsure_ * kN / 2;
}

int encode_sphere(const Sphere& parent, const double centre[3], double radius,
                  SphereSearch search) {
  return SphereEncoder(parent)(centre, radius, search);
}

int SphereEncoder::operator()(const double centre[3], double radius, SphereSearch search,
                              Sphere* decoded) const {
  const SphereTables& t = sphere_tables();
  const Sphere& parent = parent_;
  const double pr = pr_, unsure = unsure_, unsure_steps = unsure_steps_;
  const double* pc = pc_;
  double rel[3];
  for (int k = 0; k < 3; ++k) rel[k] = (centre[k] - pc[k]) / pr;
  const double rel_radius = radius / pr;
  const int first = std::clamp(static_cast<int>(std::floor(rel_radius * kN)), 1, kN);
  auto offer = [&](int s, double& dist, Sphere& d) {
    if (s < 0 || t.inside[s] < -unsure) return Offer::kNotInParent;  // clearly outside
    d = decode_sphere(t.cells[s], parent);
    const double room = d.radius - radius;
    const double dx = d.centre.x - centre[0], dy = d.centre.y - centre[1],
                 dz = d.centre.z - centre[2];
    const double dist2 = dx * dx + dy * dy + dz * dz;
    if (room < 0 || dist2 > room * room * (1 + 1e-9)) return Offer::kTooSmall;  // clearly
    dist = std::sqrt(dist2);
    if (dist + radius > d.radius) return Offer::kTooSmall;  // must contain the true sphere
    // ... and lie inside the parent
    if (t.inside[s] <= unsure && distance(d.centre, pc) + d.radius > pr) return Offer::kNotInParent;
    return Offer::kFits;
  };
  auto cell = [&](int size, int x, int y, int z) {
    return t.index[size - 1 + kN * (x + kN * (y + kN * z))];
  };
  // The child's centre in units of the cell grid's half step, (rel + 1) * 13.
  const double grid[3] = {(rel[0] + 1) * kN, (rel[1] + 1) * kN, (rel[2] + 1) * kN};
  for (int size = first; size <= kN; ++size) {
    const double slack = kCellRadius[size] - rel_radius;
    if (slack < 0) continue;
    // Where the child's centre falls on each axis's grid of cell centres ((size + 2x)/13 − 1,
    // in parent radii): `steps` grid steps from the first.
    double steps[3];
    double e2 = 0;
    for (int k = 0; k < 3; ++k) {
      steps[k] = (grid[k] - size) / 2;
      // The nearest index, floor(steps + 0.5) (steps > -6.6 for a child inside its parent),
      // kept in the box.
      const int nearest = std::clamp(static_cast<int>(steps[k] + 16.5) - 16, 0, kN - size);
      const double e = (steps[k] - nearest) * (2.0 / kN);
      e2 += e * e;
    }
    // No cell of this size comes closer than the one nearest on every axis (exact arithmetic):
    // when that one misses the child by more than rounding explains, they all do.
    const double reach = slack * (1 + 1e-6) + 4 * unsure;
    if (size < kN && e2 > reach * reach) continue;
    // Nearest first. Whether a cell contains the child depends only on its distance (the cells
    // of one size share their radius), and along each axis the decoded coordinate depends only
    // on that axis's index: so unless a cell fails for the parent, the cell that is nearest on
    // every axis decides. Its candidates per axis: the nearest index, and the second nearest
    // when the two are too close to tell apart after float rounding. If any of them is not
    // proved inside the parent (a farther cell might then be the answer), or lies farther than
    // R − radius from the child on an axis (outside the box below), or rounding is too coarse
    // for the grid, every cell in the box is tried, as the exhaustive search does.
    bool decided = search == SphereSearch::kNearestFirst && unsure_steps < 0.05;
    int near[3][2], count[3] = {0, 0, 0};
    const double slack_steps = slack * kN / 2;  // R − radius in grid steps
    for (int k = 0; k < 3 && decided; ++k) {
      const int below = floor_int(steps[k]);
      const double frac = steps[k] - below;
      const int nearest = below + (frac < 0.5 ? 0 : 1);
      const int other = below + (frac < 0.5 ? 1 : 0);
      auto in_box = [&](int x) {
        return x >= 0 && x <= kN - size && std::fabs(steps[k] - x) <= slack_steps;
      };
      if (!in_box(nearest)) decided = false;
      near[k][count[k]++] = nearest;
      if (std::fabs(1 - 2 * frac) <= 4 * unsure_steps && in_box(other))
        near[k][count[k]++] = other;
      if (count[k] == 2 && near[k][0] > near[k][1]) std::swap(near[k][0], near[k][1]);
    }
    // The nearest cell of this size that contains the child.
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    Sphere best_sphere{};
    auto consider = [&](int s) {
      double dist = 0;
      Sphere d;
      const Offer o = offer(s, dist, d);
      if (o == Offer::kFits && dist < best_d) {
        best_d = dist;
        best = s;
        best_sphere = d;
      }
      return o;
    };
    if (decided) {
      for (int a = 0; a < count[0] && decided; ++a)
        for (int b = 0; b < count[1] && decided; ++b)
          for (int c = 0; c < count[2] && decided; ++c)
            if (consider(cell(size, near[0][a], near[1][b], near[2][c])) == Offer::kNotInParent)
              decided = false;
      if (!decided) {
        best = -1;
        best_d = std::numeric_limits<double>::infinity();
      }
    }
    if (!decided) {
      // Cell centres within R − radius of the child on every axis: the only ones that can
      // contain it.
      int lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::max(0, ceil_int(((rel[k] - slack + 1) * kN - size) / 2));
        hi[k] = std::min(kN - size, floor_int(((rel[k] + slack + 1) * kN - size) / 2));
      }
      for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int z = lo[2]; z <= hi[2]; ++z) consider(cell(size, x, y, z));
    }
    // No cell of this size contains the child (when the nearest does not, none does).
    if (best < 0) continue;
    if (decoded) *decoded = best_sphere;
    return best;
  }
  return -1;
}

int SphereEncoder::nearest_disc(const double centre[3], double radius, const Vec3f& n,
                                Sphere* decoded) const {
  const SphereTables& t = sphere_tables();
  double grid[3];  // the leaf's centre in units of the cell grid's half step, (rel + 1) * 13
  for (int k = 0; k < 3; ++k) grid[k] = ((centre[k] - pc_[k]) / pr_ + 1) * kN;
  int best = -1;
  double best_e = std::numeric_limits<double>::infinity();
  auto consider = [&](int size, int x, int y, int z) {
    const int s = t.index[size - 1 + kN * (x + kN * (y + kN * z))];
    if (s < 0 || t.inside[s] < -unsure_) return;
    const Sphere d = decode_sphere(t.cells[s], parent_);
    if (t.inside[s] <= unsure_ && distance(d.centre, pc_) + d.radius > pr_) return;
    const double dx = d.centre.x - centre[0], dy = d.centre.y - centre[1],
                 dz = d.centre.z - centre[2];
    const double across = std::fabs(dx * n.x + dy * n.y + dz * n.z);
    const double along = std::sqrt(std::max(0.0, dx * dx + dy * dy + dz * dz - across * across));
    // The band the drawn disc adds around the splat's (its edge at most r' + along from c), and
    // the band of the splat it leaves bare seen at up to atan(kDiscSlope) from the normal.
    const double grown = std::max(0.0, d.radius + along - radius);
    const double bare = std::max(0.0, radius + along + kDiscSlope * across - d.radius);
    const double e = grown + kBareWeight * bare;
    if (e < best_e) {
      best_e = e;
      best = s;
      if (decoded) *decoded = d;
    }
  };
  // Per axis, the indices of the cell centres of one size nearest the leaf's: `wide` takes the
  // two around it, else the nearest alone.
  auto around = [&](int size, int k, bool wide, int& lo, int& hi) {
    const double steps = (grid[k] - size) / 2;
    const int below = floor_int(steps);
    if (wide) {
      lo = std::max(0, below);
      hi = std::min(kN - size, below + 1);
      if (lo > hi) lo = hi = std::clamp(below, 0, kN - size);
    } else {
      lo = hi = std::clamp(below + (steps - below < 0.5 ? 0 : 1), 0, kN - size);
    }
  };
  const int below = std::clamp(floor_int(radius / pr_ * kN), 1, kN - 1);
  // The first pass, one cell per size (nearly always the last: 1473 of 1M leaves of a torus
  // mesh go on), written out without the loops over a box of cells.
  for (int size = below; size <= below + 1; ++size) {
    int at[3];
    for (int k = 0; k < 3; ++k) around(size, k, false, at[k], at[k]);
    consider(size, at[0], at[1], at[2]);
  }
  for (int pass = 1; pass < 3 && best < 0; ++pass) {
    const int s0 = pass == 1 ? std::max(1, below - 1) : 1;
    const int s1 = pass == 1 ? std::min(kN, below + 2) : kN;
    for (int size = s0; size <= s1; ++size) {
      int lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        if (pass < 2) {
          around(size, k, pass == 1, lo[k], hi[k]);
        } else {
          lo[k] = 0;
          hi[k] = kN - size;
        }
      }
      for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int z = lo[2]; z <= hi[2]; ++z) consider(size, x, y, z);
    }
  }
  return best;
}

int encode_normal(const Vec3f& n) {
  const float ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  if (!(ax + ay + az > 0))
    return (4 * kNormalSteps + kNormalSteps / 2) * kNormalSteps + kNormalSteps / 2;
  // The original's choice of the dominant axis (written for selects: random normals make it a
  // coin flip for a branch).
  const bool x_over_y = ax > ay;
  const int axis = (x_over_y ? ax : ay) > az ? (x_over_y ? 0 : 1) : 2;
  const float in[3] = {n.x, n.y, n.z};
  const int a = 2 * axis + (in[axis] > 0 ? 0 : 1);
  const Vec3f m = normalized(n);
  const float mc[3] = {m.x, m.y, m.z};
  const int u0 = warp_index(mc[(axis + 1) % 3]), v0 = warp_index(mc[(axis + 2) % 3]);
  const NormalComponents& t = normal_components();
  // Most normals lie near enough to the original's cell that no neighbour can be closer.
  const int own = (a * kFramed + u0 + 1) * kFramed + v0 + 1;
  const int own_code = (a * kNormalSteps + u0) * kNormalSteps + v0;
  if (t.x[own] * m.x + t.y[own] * m.y + t.z[own] * m.z > t.own_wins[own]) return own_code;
  // The closeness (dot product) of the 3 × 3 codes around (u0, v0), row by row: entry
  // (a, u0, v0) of the framed table is code (a, u0 − 1, v0 − 1).
  const int corner = (a * kFramed + u0) * kFramed + v0;
  float d[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int q = corner + r * kFramed + c;
      d[3 * r + c] = t.x[q] * m.x + t.y[q] * m.y + t.z[q] * m.z;
    }
  // The original's cell first, so that a tie keeps it (a neighbour must be strictly closer); then
  // its neighbours in (u, v) order: the comparisons pick, without branches.
  int best = 4;
  float best_dot = std::isnan(d[4]) ? -2.0f : d[4];  // not a unit normal: any neighbour is closer
  for (int k = 0; k < 9; ++k) {
    const bool closer = d[k] > best_dot;  // false for NaN
    best = closer ? k : best;
    best_dot = closer ? d[k] : best_dot;
  }
  return (a * kNormalSteps + u0 + best / 3 - 1) * kNormalSteps + v0 + best % 3 - 1;
}

const Vec3f& decode_normal(int code) { return normal_table()[static_cast<std::size_t>(code)]; }

int encode_cone(double theta) {
  if (theta > 1.5) return 3;
  const int c = static_cast<int>(4.0 * std::sqrt(std::sin(std::max(theta, 0.0))));
  return std::min(c, 3);
}

}  // namespace splatkit::qsplat
