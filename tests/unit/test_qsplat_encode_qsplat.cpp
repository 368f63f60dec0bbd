// build-qsplat's tree and bytes: a hand-made model pinned byte for byte, and an independent walk
// of written files as the original viewer walks them (offsets followed, groups decoded against
// their parent's decoded sphere), checking one leaf per point, conservative spheres and normals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <vector>

#include "formats/qsplat_codes.h"
#include "formats/read_qsplat.h"
#include "qsplat/build_qsplat_tree.h"
#include "qsplat/encode_qsplat.h"
#include "splatkit/synthetic_shapes.h"
#include "tbb/global_control.h"

namespace splatkit::qsplat {
namespace {

QSplatLeaves line_of_five() {
  QSplatLeaves l;
  for (int i = 0; i < 5; ++i) {
    l.positions.push_back({static_cast<float>(i), 0, 0});
    l.normals.push_back({0, 0, 1});
    l.radii.push_back(0.4f);
    l.source.push_back(static_cast<uint32_t>(i));
  }
  return l;
}

std::string hex(const std::vector<unsigned char>& b) {
  std::string s;
  char buf[8];
  for (std::size_t i = 0; i < b.size(); ++i) {
    std::snprintf(buf, sizeof buf, "0x%02X,%s", b[i], (i % 12 == 11) ? "\n" : " ");
    s += buf;
  }
  return s;
}

TEST(QSplatEncode, FivePointsOnALineArePinnedByteForByte) {
  const QSplatLeaves leaves = line_of_five();
  const QSplatTree tree = build_qsplat_tree(leaves);
  // Tree: 5 leaves, C = 4: the root has children A (leaves 0..3) and B (leaf 4); A has 4 leaves.
  ASSERT_EQ(tree.size(), 7u);
  EXPECT_EQ(tree.child_count[0], 2);
  EXPECT_EQ(tree.child_count[1], 4);
  EXPECT_EQ(tree.child_count[2], 0);
  // Tight spheres: A spans x in [-0.4, 3.4] -> (1.5, 0, 0) r 1.9; root spans [-0.4, 4.4].
  EXPECT_FLOAT_EQ(tree.spheres[1].centre.x, 1.5f);
  EXPECT_FLOAT_EQ(tree.spheres[1].radius, 1.9f);
  EXPECT_FLOAT_EQ(tree.spheres[0].centre.x, 2.0f);
  EXPECT_FLOAT_EQ(tree.spheres[0].radius, 2.4f);
  const EncodedQSplat e = encode_qsplat(tree, "");
  // clang-format off
  const std::vector<unsigned char> expected = {
    // fragment header: magic, length 68, 5 leaves, options 0 (no colour)
    'Q', 'S', 'p', 'l', 'a', 't', '1', '1', 0x00, 0x00, 0x00, 0x44,
    0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x00,
    // root centre (2, 0, 0), radius 2.4 grown by kInteriorMargin (3.0, rounded up: 0x40400001),
    // 2 children
    0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x40, 0x40, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02,
    // byte 40: root group; offset 12 -> byte 52 (A's group)
    0x00, 0x00, 0x00, 0x0C,
    // A must hold (1.5, 0, 0) r 1.9 * 1.25: S = 7589 (size 11, cell (0, 1, 1): centre 2 - 3 * 2/13,
    // radius 3 * 11/13), no grandchildren, 4 children: 7589 << 3 | 3 = 0xED2B.
    // Normal +Z: A = 4, U = V = 26: Q = 12194, << 2 | cone 0 = 0xBE88.
    0xED, 0x2B, 0xBE, 0x88,
    // B, a leaf (4, 0, 0) r 0.4: S = 4414 (size 3, cell (9, 5, 5): centre 2 + 3 * 8/13, radius
    // 3 * 3/13): 4414 << 3 = 0x89F0
    0x89, 0xF0, 0xBE, 0x88,
    // byte 52: A's group, no offset (its members are leaves): 4 leaves of size 3 inside A's
    // decoded sphere, cells (x, 5, 5) for x = 6, 4, 1 and 9: S = 4051, 3809, 3446, 4414, i.e.
    // leaves 2, 1, 0, 3 (the order the rank split left them in)
    0x7E, 0x98, 0xBE, 0x88, 0x77, 0x08, 0xBE, 0x88, 0x6B, 0xB0, 0xBE, 0x88,
    0x89, 0xF0, 0xBE, 0x88,
    // byte 68: the end (68 is a multiple of 4: no padding)
  };
  // clang-format on
  EXPECT_EQ(e.bytes, expected) << hex(e.bytes);
}

// --- the original viewer's walk, written from the format only ---

uint32_t be32(const unsigned char* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

struct WalkedLeaf {
  Sphere sphere;
  int normal_code;
};

struct Walk {
  std::vector<WalkedLeaf> leaves;  // depth first, children in file order
  std::size_t nodes = 0, bad_parent = 0;
};

// Follows the offsets as the original draw_hierarchy does: a group starts with an offset when its
// parent has grandchildren; the children of member i start where those of member i - 1 end.
void walk_group(const unsigned char* here, int count, const Sphere& parent, bool offset,
                std::size_t nb, Walk& w) {
  const unsigned char* there = nullptr;
  if (offset) {
    there = here + be32(here);
    here += 4;
  }
  for (int i = 0; i < count; ++i, here += nb) {
    const unsigned w0 = (unsigned{here[0]} << 8) | here[1];
    const Sphere s = decode_sphere(sphere_cells()[w0 >> 3], parent);
    ++w.nodes;
    const double dx = double{s.centre.x} - parent.centre.x,
                 dy = double{s.centre.y} - parent.centre.y,
                 dz = double{s.centre.z} - parent.centre.z;
    if (std::sqrt(dx * dx + dy * dy + dz * dz) + s.radius > parent.radius) ++w.bad_parent;
    const int kids = w0 & 3;
    if (kids == 0) {
      w.leaves.push_back({s, static_cast<int>(((unsigned{here[2]} << 8) | here[3]) >> 2)});
      continue;
    }
    const bool grand = w0 & 4;
    walk_group(there, kids + 1, s, grand, nb, w);
    there += nb * (kids + 1) + (grand ? 4 : 0);
  }
}

Walk walk_file(const std::vector<unsigned char>& b) {
  std::size_t at = 0;
  while (be32(&b[at + 16]) & 2) at += be32(&b[at + 8]);  // comment fragments
  const unsigned char* f = &b[at];
  float v[4];
  for (int k = 0; k < 4; ++k) {
    const uint32_t u = be32(f + 20 + 4 * k);
    std::memcpy(&v[k], &u, 4);
  }
  Walk w;
  walk_group(f + 40, static_cast<int>(be32(f + 36)), {{v[0], v[1], v[2]}, v[3]}, true,
             (be32(f + 16) & 1) ? 6 : 4, w);
  EXPECT_EQ(be32(f + 12), w.leaves.size());
  return w;
}

// The builder's leaves in the same depth-first order.
void leaves_depth_first(const QSplatTree& t, uint32_t i, std::vector<uint32_t>& out) {
  if (t.child_count[i] == 0) {
    out.push_back(t.leaf[i]);
    return;
  }
  for (int k = 0; k < t.child_count[i]; ++k) leaves_depth_first(t, t.first_child[i] + k, out);
}

void check_structure(const QSplatLeaves& leaves, bool centroid_rule) {
  const QSplatTree tree = build_qsplat_tree(leaves, centroid_rule);
  const EncodedQSplat e = encode_qsplat(tree, "comment made by hand\n");
  const Walk w = walk_file(e.bytes);
  ASSERT_EQ(w.leaves.size(), leaves.size());
  EXPECT_EQ(w.bad_parent, 0u);
  std::vector<uint32_t> order;
  leaves_depth_first(tree, 0, order);
  ASSERT_EQ(order.size(), leaves.size());
  std::vector<int> seen(leaves.size(), 0);
  double worst_normal = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const uint32_t p = order[k];
    ++seen[p];
    const Sphere& s = w.leaves[k].sphere;
    const Vec3f c = leaves.positions[p];
    const double dx = double{s.centre.x} - c.x, dy = double{s.centre.y} - c.y,
                 dz = double{s.centre.z} - c.z;
    EXPECT_LE(std::sqrt(dx * dx + dy * dy + dz * dz) + leaves.radii[p], double{s.radius}) << p;
    const Vec3f& n = decode_normal(w.leaves[k].normal_code);
    worst_normal =
        std::max(worst_normal, std::acos(std::min(1.0, double{dot(n, leaves.normals[p])})));
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_LE(worst_normal, kNormalMaxError);
  // The reader agrees with the walk.
  const QSplatModel m = parse_qsplat(e.bytes, "walk.qs");
  EXPECT_EQ(m.leaves, leaves.size());
  EXPECT_EQ(m.size(), w.nodes + 1);
  EXPECT_EQ(m.comments, "comment made by hand\n");
  EXPECT_EQ(m.has_color, !leaves.colors.empty());
}

QSplatLeaves shape_leaves(ShapeKind kind, std::size_t n, bool color) {
  ShapeOptions o;
  o.kind = kind;
  o.points = n;
  o.random = true;
  const SplatCloud c = make_shape(o);
  QSplatLeaves l;
  l.positions = c.positions;
  l.normals = c.normals;
  l.radii = c.radii;
  for (std::size_t i = 0; i < c.size(); ++i) {
    l.source.push_back(static_cast<uint32_t>(i));
    if (color) l.colors.push_back({static_cast<uint8_t>(i), static_cast<uint8_t>(i >> 3), 200});
  }
  return l;
}

TEST(QSplatEncode, TheOriginalWalkReachesEveryPointOnceInsideItsLeaf) {
  check_structure(line_of_five(), false);
  check_structure(shape_leaves(ShapeKind::kSphere, 5000, false), false);
  check_structure(shape_leaves(ShapeKind::kTorus, 7001, true), false);
  check_structure(shape_leaves(ShapeKind::kCadPart, 3000, false), true);
}

TEST(QSplatEncode, CoincidentPointsStillSplit) {
  QSplatLeaves l = line_of_five();
  for (int i = 0; i < 40; ++i) {
    l.positions.push_back({1, 1, 1});
    l.normals.push_back({0, 1, 0});
    l.radii.push_back(0.01f);
    l.source.push_back(static_cast<uint32_t>(l.source.size()));
  }
  check_structure(l, false);
}

TEST(QSplatEncode, TightSpheresAreSmallerThanTheCentroidRule) {
  const QSplatTree t = build_qsplat_tree(shape_leaves(ShapeKind::kTorus, 20000, false));
  EXPECT_LT(t.mean_interior_radius, t.mean_interior_radius_centroid);
  RecordProperty("tight_over_centroid",
                 std::to_string(t.mean_interior_radius / t.mean_interior_radius_centroid));
}

TEST(QSplatEncode, BytesDoNotDependOnTheThreadCount) {
  const QSplatLeaves l = shape_leaves(ShapeKind::kCadPart, 30000, true);
  std::vector<unsigned char> one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = encode_qsplat(build_qsplat_tree(l), "x").bytes;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = encode_qsplat(build_qsplat_tree(l), "x").bytes;
  }
  EXPECT_EQ(one, many);
}

}  // namespace
}  // namespace splatkit::qsplat
