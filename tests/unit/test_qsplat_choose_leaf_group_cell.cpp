// choose_leaf_group_cell (qsplat/choose_leaf_group_cell.h) and the pair split of large leaves
// (build_qsplat_tree.h, kPairLeavesAbove): the group's cell lies inside its grandparent, its
// leaves placed by nearest_disc come nearer their splats (by the search's own measure) than under
// the smallest containing cell, and a node of 4 leaves with a large one becomes two pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "qsplat/build_qsplat_tree.h"
#include "qsplat/choose_leaf_group_cell.h"
#include "qsplat/enclose_spheres.h"

namespace splatkit::qsplat {
namespace {

double distance(const Vec3f& a, const Vec3f& b) {
  const double dx = double{a.x} - b.x, dy = double{a.y} - b.y, dz = double{a.z} - b.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// The search's measure, on the leaves as nearest_disc really places them under `p`.
double placed_cost(const Sphere& p, const Sphere* leaves, const uint16_t* codes, int count) {
  const SphereEncoder encode(p);
  double cost = 0;
  for (int k = 0; k < count; ++k) {
    const double c[3] = {leaves[k].centre.x, leaves[k].centre.y, leaves[k].centre.z};
    const Vec3f& n = decode_normal(codes[k]);
    Sphere d;
    encode.nearest_disc(c, leaves[k].radius, n, &d);
    const Vec3f v = d.centre - leaves[k].centre;
    const double across = std::fabs(double{dot(v, n)});
    const double along = std::sqrt(std::max(0.0, double{squared_norm(v)} - across * across));
    const double r = leaves[k].radius;
    cost += r * (std::max(0.0, d.radius + along - r) +
                 kLeafGroupBareWeight * std::max(0.0, r + along + kDiscSlope * across - d.radius));
  }
  return cost;
}

TEST(QSplatLeafGroup, TheChosenCellLiesInsideAndPlacesTheLeavesNoWorse) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1), size(0.05f, 0.3f);
  const Sphere grandparent{{0.3f, -0.2f, 0.1f}, 2.0f};
  const SphereEncoder encode(grandparent);
  int better = 0, groups = 0;
  for (int g = 0; g < 400; ++g) {
    // 2-4 coplanar leaves (normal +Z) somewhere inside the grandparent.
    const int count = 2 + g % 3;
    const Vec3f at{0.8f * u(rng), 0.8f * u(rng), 0.8f * u(rng)};
    Sphere leaves[4];
    uint16_t codes[4];
    for (int k = 0; k < count; ++k) {
      leaves[k] = {grandparent.centre + at + Vec3f{0.3f * u(rng), 0.3f * u(rng), 0}, size(rng)};
      codes[k] = static_cast<uint16_t>(encode_normal({0, 0, 1}));
    }
    const Sphere tight = enclose_spheres(leaves, count);
    const double c[3] = {tight.centre.x, tight.centre.y, tight.centre.z};
    Sphere containing;
    const int code = encode(c, tight.radius, SphereSearch::kNearestFirst, &containing);
    ASSERT_GE(code, 0);
    Sphere chosen;
    const int s =
        choose_leaf_group_cell(grandparent, tight, code, containing, leaves, codes, count, &chosen);
    ASSERT_GE(s, 0);
    ASSERT_LT(s, kSphereCells);
    // The decoded sphere of the code returned, inside the grandparent as a reader decodes it.
    const Sphere decoded = decode_sphere(sphere_cells()[static_cast<std::size_t>(s)], grandparent);
    EXPECT_EQ(decoded.centre, chosen.centre);
    EXPECT_EQ(decoded.radius, chosen.radius);
    EXPECT_LE(distance(decoded.centre, grandparent.centre) + decoded.radius,
              double{grandparent.radius});
    // Never worse than the containing cell, on the leaves as nearest_disc places them.
    const double before = placed_cost(containing, leaves, codes, count);
    const double after = placed_cost(chosen, leaves, codes, count);
    EXPECT_LE(after, before) << "group " << g;
    better += after < before * 0.95;
    ++groups;
  }
  // The containing cell is rarely the best for the leaves.
  EXPECT_GT(better, groups / 3);
}

TEST(QSplatLeafGroup, FourLeavesWithALargeOneBecomeTwoPairs) {
  // 32 leaves on a line: two nodes of 16, each over 4 nodes of 4 consecutive leaves. Leaf 30 is
  // large, so the node of leaves 28..31 splits into two pairs.
  QSplatLeaves leaves;
  for (int i = 0; i < 32; ++i) {
    leaves.positions.push_back({static_cast<float>(i), 0, 0});
    leaves.normals.push_back({0, 0, 1});
    // Half the box's diagonal is 15.5: kPairLeavesAbove of it is 0.155.
    leaves.radii.push_back(i == 30 ? 1.0f : 0.1f);
  }
  const QSplatTree t = build_qsplat_tree(leaves);
  int pairs_over_pairs = 0, fours = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const int c = t.child_count[i];
    if (c == 0) continue;
    bool all_leaves = true, all_pairs = true;
    for (int k = 0; k < c; ++k) {
      const uint32_t j = t.first_child[i] + static_cast<uint32_t>(k);
      all_leaves &= t.child_count[j] == 0;
      all_pairs &= t.child_count[j] == 2 && t.child_count[t.first_child[j]] == 0 &&
                   t.child_count[t.first_child[j] + 1] == 0;
    }
    fours += all_leaves && c == 4;
    pairs_over_pairs += c == 2 && all_pairs;
  }
  EXPECT_EQ(pairs_over_pairs, 1);  // leaves 28..31
  EXPECT_EQ(fours, 7);             // leaves 0..27, all small
}

}  // namespace
}  // namespace splatkit::qsplat
