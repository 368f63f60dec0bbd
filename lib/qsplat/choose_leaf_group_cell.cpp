#include "qsplat/choose_leaf_group_cell.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace splatkit::qsplat {

namespace {

constexpr int kN = 13;

// [size − 1 + 13·(x + 13·(y + 13·z))] -> the cell's code, or -1 (the table's own order:
// qsplat_codes.h).
const std::array<int16_t, kN * kN * kN * kN>& cell_index() {
  static const std::array<int16_t, kN* kN* kN* kN> index = [] {
    std::array<int16_t, kN * kN * kN * kN> a{};
    a.fill(-1);
    const auto& cells = sphere_cells();
    for (int s = 0; s < kSphereCells; ++s) {
      const SphereCell& c = cells[static_cast<std::size_t>(s)];
      const int size = static_cast<int>(std::lround(c.r * kN));
      auto at = [&](float v) { return static_cast<int>(std::lround(((v + 1) * kN - size) / 2)); };
      a[static_cast<std::size_t>(size - 1 + kN * (at(c.x) + kN * (at(c.y) + kN * at(c.z))))] =
          static_cast<int16_t>(s);
    }
    return a;
  }();
  return index;
}

double distance(const Vec3f& a, const double b[3]) {
  const double dx = a.x - b[0], dy = a.y - b[1], dz = a.z - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}
double distance(const Vec3f& a, const Vec3f& b) {
  const double b3[3] = {b.x, b.y, b.z};
  return distance(a, b3);
}

// r · (grown + kLeafGroupBareWeight · bare) of the decoded leaf `d` of a splat (c, r, n).
double disc_cost(const Sphere& d, const double c[3], double r, const Vec3f& n) {
  const double v[3] = {d.centre.x - c[0], d.centre.y - c[1], d.centre.z - c[2]};
  const double across = std::fabs(v[0] * n.x + v[1] * n.y + v[2] * n.z);
  const double along =
      std::sqrt(std::max(0.0, v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - across * across));
  return r * (std::max(0.0, d.radius + along - r) +
              kLeafGroupBareWeight * std::max(0.0, r + along + kDiscSlope * across - d.radius));
}

// The cost of one leaf (true sphere c, r, decoded normal n) under the decoded sphere (pc, pr), as
// the first pass of SphereEncoder::nearest_disc places it (for the two cell sizes around
// 13·r/pr, the cell nearest c on every axis; of those inside the parent, the one of least
// grown + kBareWeight·bare), in double without the float decoding: a guide for the choice, the
// leaf itself is encoded by nearest_disc afterwards. A leaf that neither cell holds: -1.
double leaf_cost(const double pc[3], double pr, const Sphere& leaf, const Vec3f& n) {
  const double c[3] = {leaf.centre.x, leaf.centre.y, leaf.centre.z};
  const double r = leaf.radius;
  const int below = std::clamp(static_cast<int>(std::floor(r / pr * kN)), 1, kN - 1);
  double best_e = HUGE_VAL, best_cost = -1;
  // The nearest cells, then (a leaf near the parent's edge) those one step nearer its centre.
  for (int inward = 0; inward < 2 && best_cost < 0; ++inward)
    for (int size = below; size <= below + 1; ++size) {
      double d[3], cell2 = 0;
      for (int k = 0; k < 3; ++k) {
        const double steps = (((c[k] - pc[k]) / pr + 1) * kN - size) / 2;
        int x = std::clamp(static_cast<int>(std::floor(steps + 0.5)), 0, kN - size);
        if (inward) x += 2 * x + size < kN ? 1 : 2 * x + size > kN ? -1 : 0;
        const double cell = (size + 2.0 * x) / kN - 1;  // the cell centre, parent radii
        cell2 += cell * cell;
        d[k] = pc[k] + pr * cell - c[k];
      }
      const double rr = pr * size / kN;
      if (std::sqrt(cell2) + static_cast<double>(size) / kN > 1) continue;  // not inside
      const double across = std::fabs(d[0] * n.x + d[1] * n.y + d[2] * n.z);
      const double dist2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double along = std::sqrt(std::max(0.0, dist2 - across * across));
      const double e = std::max(0.0, rr + along - r) +
                       kBareWeight * std::max(0.0, r + along + kDiscSlope * across - rr);
      if (e < best_e) {
        best_e = e;
        best_cost =
            r * (std::max(0.0, rr + along - r) +
                 kLeafGroupBareWeight * std::max(0.0, r + along + kDiscSlope * across - rr));
      }
    }
  return best_cost;
}

// The group's cost under the decoded sphere `p`, or a value >= `give_up` as soon as the leaves
// so far reach it.
double group_cost(const Sphere& p, const Sphere* leaves, const uint16_t* normal_codes, int count,
                  double give_up) {
  const double pc[3] = {p.centre.x, p.centre.y, p.centre.z};
  double cost = 0;
  for (int k = 0; k < count && cost < give_up; ++k) {
    const Vec3f& n = decode_normal(normal_codes[k]);
    double e = leaf_cost(pc, p.radius, leaves[k], n);
    if (e < 0) {  // near the edge: nearest_disc's own search
      const Sphere& s = leaves[k];
      const double c[3] = {s.centre.x, s.centre.y, s.centre.z};
      Sphere d;
      SphereEncoder(p).nearest_disc(c, s.radius, n, &d);
      e = disc_cost(d, c, s.radius, n);
    }
    cost += e;
  }
  return cost;
}

// The cost of the leaves as SphereEncoder::nearest_disc really places them under `p`.
double placed_cost(const Sphere& p, const Sphere* leaves, const uint16_t* normal_codes, int count) {
  const SphereEncoder encode(p);
  double cost = 0;
  for (int k = 0; k < count; ++k) {
    const Sphere& s = leaves[k];
    const Vec3f& n = decode_normal(normal_codes[k]);
    const double c[3] = {s.centre.x, s.centre.y, s.centre.z};
    Sphere d;
    encode.nearest_disc(c, s.radius, n, &d);
    cost += disc_cost(d, c, s.radius, n);
  }
  return cost;
}

}  // namespace

int choose_leaf_group_cell(const Sphere& grandparent, const Sphere& tight, int containing_code,
                           const Sphere& containing, const Sphere* leaves,
                           const uint16_t* normal_codes, int count, Sphere* decoded) {
  const auto& cells = sphere_cells();
  const auto& index = cell_index();
  const double gc[3] = {grandparent.centre.x, grandparent.centre.y, grandparent.centre.z};
  const double tc[3] = {tight.centre.x, tight.centre.y, tight.centre.z};
  const double g = grandparent.radius, t = tight.radius;
  const double reach = kLeafGroupCentreReach * t;
  int best = containing_code;
  Sphere best_sphere = containing;
  double best_cost = group_cost(containing, leaves, normal_codes, count, HUGE_VAL);
  for (int size = 1; size <= kN; ++size) {
    const double r = g * size / kN;
    if (r < kLeafGroupRadiusLow * t * 0.999 || r > kLeafGroupRadiusHigh * t * 1.001) continue;
    // Per axis, the cell centres ((size + 2x)/13 − 1 grandparent radii from its centre) within
    // `reach` of the node's.
    int lo[3], hi[3];
    bool empty = false;
    for (int k = 0; k < 3; ++k) {
      const double at = ((tc[k] - gc[k]) / g + 1) * kN - size;  // 2x at the node's centre
      lo[k] = std::max(0, static_cast<int>(std::ceil((at - reach / g * kN) / 2)));
      hi[k] = std::min(kN - size, static_cast<int>(std::floor((at + reach / g * kN) / 2)));
      empty |= lo[k] > hi[k];
    }
    if (empty) continue;
    for (int x = lo[0]; x <= hi[0]; ++x)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int z = lo[2]; z <= hi[2]; ++z) {
          const int s = index[static_cast<std::size_t>(size - 1 + kN * (x + kN * (y + kN * z)))];
          if (s < 0 || s == containing_code) continue;
          const Sphere d = decode_sphere(cells[static_cast<std::size_t>(s)], grandparent);
          // Inside the decoded grandparent, as a reader computes it (double on the float values).
          if (distance(d.centre, gc) + d.radius > g) continue;
          if (d.radius < kLeafGroupRadiusLow * t || d.radius > kLeafGroupRadiusHigh * t ||
              distance(d.centre, tc) > reach)
            continue;
          // Every decoded leaf lies inside d, so a splat reaching out of d by e costs at least
          // r·e; and a splat whose centre lies outside d, or nearly, would lose half its disc
          // (skipped: its leaf's search would fall back to every cell).
          double bound = 0;
          bool near_edge = false;
          for (int k = 0; k < count; ++k) {
            const double out = distance(d.centre, leaves[k].centre) - d.radius;
            bound += leaves[k].radius * std::max(0.0, out + leaves[k].radius);
            near_edge |= out + 0.5 * leaves[k].radius > 0;
          }
          if (near_edge || bound >= best_cost) continue;
          const double cost = group_cost(d, leaves, normal_codes, count, best_cost);
          if (cost < best_cost) {
            best_cost = cost;
            best = s;
            best_sphere = d;
          }
        }
  }
  // The search follows a model of nearest_disc's first pass; the cell it found is kept only when
  // the leaves nearest_disc really places in it cost no more than in the containing cell.
  if (best != containing_code && placed_cost(best_sphere, leaves, normal_codes, count) >
                                     placed_cost(containing, leaves, normal_codes, count)) {
    best = containing_code;
    best_sphere = containing;
  }
  if (decoded) *decoded = best_sphere;
  return best;
}

}  // namespace splatkit::qsplat
