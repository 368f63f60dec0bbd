// The cut property of a Sequential Point Tree's list after quantisation (spt/encode_spt.h read back
// with formats/read_spt.h): for any view distance r, every root-to-leaf path of the tree has
// exactly one entry with r_min <= r < r_max (no hole, no double cover), on real and synthetic
// clouds, compact and full precision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "formats/read_cloud.h"
#include "formats/read_spt.h"
#include "splatkit/synthetic_shapes.h"
#include "spt/build_spt_tree.h"
#include "spt/encode_spt.h"

namespace splatkit::spt {
namespace {

// Checks every leaf's path at `distances`; returns the number of (leaf, distance) failures.
std::size_t cut_failures(const EncodedSpt& file, const SptModel& m, std::size_t n,
                         const std::vector<float>& distances) {
  std::size_t failures = 0;
  for (std::size_t leaf = 0; leaf < n; ++leaf)
    for (float r : distances) {
      int covered = 0;
      for (uint32_t i = static_cast<uint32_t>(leaf); i != kNoParent; i = file.parent[i]) {
        const uint32_t e = file.entry_of_node[i];
        if (e != kNoParent && m.r_min[e] <= r && r < m.r_max[e]) ++covered;
      }
      failures += covered != 1;
    }
  return failures;
}

void check_cut(const SplatCloud& cloud, bool full, uint64_t seed) {
  EncodeSptOptions o;
  o.full = full;
  const SptBytes built = build_spt_bytes(cloud, 1.0f, o, true);
  const EncodedSpt& file = built.info;
  const SptModel m = parse_spt(built.bytes, "t.spt");
  ASSERT_EQ(m.size(), file.entries);
  // Random distances: log-uniform over the stored range and beyond, plus every 97th stored r_min
  // exactly (the boundaries, where a hole or a double cover would show).
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(std::log(m.header.r_lo) - 1,
                                           std::log(m.header.r_hi) + 1);
  std::vector<float> distances = {0.0f};
  for (int k = 0; k < 100; ++k) distances.push_back(static_cast<float>(std::exp(u(rng))));
  for (std::size_t e = 0; e < m.size(); e += 97) distances.push_back(m.r_min[e]);
  EXPECT_EQ(cut_failures(file, m, cloud.size(), distances), 0u);
  // The intervals are not all trivial: some distance draws interior entries.
  std::size_t interior_drawn = 0;
  const float mid = std::sqrt(m.header.r_lo * m.header.r_hi);
  for (std::size_t e = 0; e < m.size(); ++e)
    interior_drawn += m.r_min[e] > 0 && m.r_min[e] <= mid && mid < m.r_max[e];
  EXPECT_GT(interior_drawn, 0u);
}

TEST(SptCutProperty, HoldsOnARealScanAfterQuantisation) {
  const std::string path = std::string(SPLATKIT_SOURCE_DIR) + "/data-samples/cad.ply";
  LoadedCloud doc = read_cloud(path);
  for (Vec3f& n : doc.cloud.normals) n = normalized(n);
  check_cut(doc.cloud, false, 1);
  check_cut(doc.cloud, true, 2);
}

TEST(SptCutProperty, HoldsOnRandomAndScanLineSamplingWithNoise) {
  ShapeOptions s;
  s.kind = ShapeKind::kTwoSpheres;
  s.points = 6000;
  s.random = true;
  s.noise = 0.002;
  check_cut(make_shape(s), false, 3);
  s.kind = ShapeKind::kTorus;
  s.scan_lines = 8;
  s.seed = 7;
  check_cut(make_shape(s), false, 4);
}

TEST(SptCutProperty, HoldsWithDuplicatesAndLargeCoordinates) {
  ShapeOptions s;
  s.kind = ShapeKind::kCube;
  s.points = 3000;
  s.random = true;
  SplatCloud c = make_shape(s);
  for (std::size_t i = 0; i < 500; ++i) {  // exact duplicates, and a far outlier
    c.positions.push_back(c.positions[i]);
    c.normals.push_back(c.normals[i]);
    c.radii.push_back(c.radii[i]);
    c.colors.push_back(c.colors[i]);
  }
  c.positions.push_back({5e3f, -4e3f, 2e3f});
  c.normals.push_back({0, 0, 1});
  c.radii.push_back(0.01f);
  c.colors.push_back({0, 0, 0});
  c.extras.clear();
  check_cut(c, false, 5);
}

TEST(SptCutProperty, SameBytesForAnyThreadCountAndSortedByRMax) {
  ShapeOptions s;
  s.kind = ShapeKind::kSphere;
  s.points = 20000;
  s.random = true;
  const SplatCloud c = make_shape(s);
  SptBytes a, b;
  tbb::task_arena(1).execute([&] { a = build_spt_bytes(c, 1.0f, {}, true); });
  tbb::task_arena(2).execute([&] { b = build_spt_bytes(c, 1.0f, {}, true); });
  EXPECT_EQ(a.info.parent, b.info.parent);
  EXPECT_EQ(a.bytes, b.bytes);
  const SptModel m = parse_spt(a.bytes, "t.spt");
  for (std::size_t e = 1; e < m.size(); ++e) ASSERT_GE(m.r_max[e - 1], m.r_max[e]);
  EXPECT_EQ(m.leaves, c.size());  // leaves have r_min = 0 and a parent with an error
  EXPECT_TRUE(std::isinf(m.r_max[0]));
  EXPECT_LT(static_cast<double>(m.size()), 2.0 * static_cast<double>(c.size()));
}

// The list through a sink of each kind: appended only (one piece), appended and patched (four
// slabs in order), reserved and patched at places, reserved and written through at aligned
// places (kSptBlock): the same bytes every time.
std::vector<unsigned char> encoded_through(const SplatCloud& cloud, int kind) {
  SplatCloud copy = cloud;
  SptSplats splats = take_spt_splats(copy);
  const SptOrder order = sort_spt_splats(splats);
  SptTree tree = build_spt_tree(splats, order, {1.0f, false});
  std::vector<unsigned char> bytes;
  SptSink sink;
  sink.write = [&](const unsigned char* p, std::size_t k) { bytes.insert(bytes.end(), p, p + k); };
  auto put = [&](uint64_t at, const unsigned char* p, std::size_t k) {
    ASSERT_LE(at + k, bytes.size());
    std::copy(p, p + k, bytes.begin() + static_cast<std::ptrdiff_t>(at));
  };
  if (kind >= 1) sink.patch = put;
  if (kind >= 2)
    sink.reserve = [&](uint64_t total) {
      bytes.assign(total, 0xEE);  // not zeros: every byte must be written
      return true;
    };
  if (kind >= 3)
    sink.write_through = [&](uint64_t at, const unsigned char* p, std::size_t k) {
      EXPECT_EQ(at % kSptBlock, 0u);
      EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % kSptBlock, 0u);
      put(at, p, k);
    };
  encode_spt(tree, splats, {}, sink);
  return bytes;
}

TEST(SptCutProperty, SameBytesThroughEveryKindOfSink) {
  ShapeOptions s;
  s.kind = ShapeKind::kSphere;
  s.random = true;
  for (std::size_t points : {7, 300, 20000}) {
    s.points = points;
    const SplatCloud c = make_shape(s);
    const std::vector<unsigned char> appended = encoded_through(c, 0);
    ASSERT_GT(appended.size(), 128u);
    EXPECT_EQ(appended, build_spt_bytes(c, 1.0f, {}).bytes);
    for (int kind = 1; kind <= 3; ++kind)
      EXPECT_EQ(encoded_through(c, kind), appended) << points << " points, sink kind " << kind;
  }
}

}  // namespace
}  // namespace splatkit::spt
