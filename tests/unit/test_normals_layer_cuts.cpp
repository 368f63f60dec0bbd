// layer_cuts: the two faces of a noisy thin slab told apart point by point (where a single edge's
// angle cannot), nothing on a noisy plane, and a step (two levels side by side) not read as a
// slab.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "normals/layer_cuts.h"
#include "normals/orient_normals_mst.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"

namespace splatkit {
namespace {

constexpr float kSpacing = 0.1f;
constexpr float kNoise = 0.3f * kSpacing;  // sigma along the normal, as the scan test set's

struct Cloud {
  std::vector<Vec3f> positions, normals;
  std::vector<int> face;  // which sheet each point was sampled on
};

// A jittered grid of `size` × `size` m at height z, noise along z, unoriented normals.
void add_sheet(Cloud& c, float x0, float size, float z, int face, DeterministicRng& rng) {
  const int n = static_cast<int>(size / kSpacing);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const float x = x0 + (static_cast<float>(i) + rng.uniformf()) * kSpacing;
      const float y = (static_cast<float>(j) + rng.uniformf()) * kSpacing;
      c.positions.push_back({x, y, z + kNoise * static_cast<float>(rng.normal())});
      c.normals.push_back({0, 0, rng.uniformf() < 0.5f ? 1.0f : -1.0f});
      c.face.push_back(face);
    }
}

std::vector<uint32_t> rows_of(const Cloud& c) {
  const SpatialIndex index(c.positions);
  std::vector<uint32_t> rows(c.positions.size() * (kOrientK - 1));
  index_knn_rows(index, kOrientK, rows);
  return rows;
}

// Points at least `margin` inside the sheets' square [x0, x0 + size] × [0, size].
bool inside(const Vec3f& p, float x0, float size, float margin) {
  return p.x > x0 + margin && p.x < x0 + size - margin && p.y > margin && p.y < size - margin;
}

TEST(NormalsLayerCuts, NoisyThinSlabFacesToldApart) {
  // Faces 1.6 spacings apart, noise 0.3 spacing: their tails meet.
  Cloud c;
  DeterministicRng rng(11);
  add_sheet(c, 0, 4, 0, 0, rng);
  add_sheet(c, 0, 4, 1.6f * kSpacing, 1, rng);
  const std::vector<uint32_t> rows = rows_of(c);
  const std::size_t w = kOrientK - 1;
  const std::vector<float> cut = layer_cuts(c.positions, c.normals, rows, w, {});
  std::size_t interior = 0, layered = 0, edges = 0, right = 0, steep_wrong = 0;
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    if (!inside(c.positions[i], 0, 4, 0.5f)) continue;
    ++interior;
    if (!std::isfinite(cut[i])) continue;
    ++layered;
    for (std::size_t s = 0; s < w; ++s) {
      const uint32_t j = rows[i * w + s];
      const bool across = c.face[j] != c.face[i];
      ++edges;
      right += other_layer(cut[i], c.normals[i], c.positions[i], c.positions[j]) == across;
      // What the edge's angle alone says (steep: across), for comparison.
      const Vec3f e = c.positions[j] - c.positions[i];
      steep_wrong += (std::fabs(e.z) > 0.5f * norm(e)) != across;
    }
  }
  EXPECT_GE(layered, interior * 60 / 100);  // measured: 69 %
  EXPECT_GE(static_cast<double>(right) / static_cast<double>(edges), 0.995);
  EXPECT_GT(steep_wrong, 10 * (edges - right));  // the layers tell much better than the angle
}

TEST(NormalsLayerCuts, NoisyPlaneHasOneLayer) {
  Cloud c;
  DeterministicRng rng(12);
  add_sheet(c, 0, 5, 0, 0, rng);
  const std::vector<float> cut =
      layer_cuts(c.positions, c.normals, rows_of(c), kOrientK - 1, {});
  std::size_t layered = 0;
  for (float v : cut) layered += std::isfinite(v);
  EXPECT_LE(layered, c.positions.size() / 1000);
}

TEST(NormalsLayerCuts, StepIsNotASlab) {
  // Two levels side by side, 1.6 spacings apart in height (a kerb, a slab lying on the ground):
  // the points along the step see both levels, but beside each other, not over each other.
  Cloud c;
  DeterministicRng rng(13);
  add_sheet(c, -2, 2, 0, 0, rng);
  add_sheet(c, 0, 2, 1.6f * kSpacing, 1, rng);
  const std::vector<float> cut =
      layer_cuts(c.positions, c.normals, rows_of(c), kOrientK - 1, {});
  std::size_t near_step = 0, layered = 0;
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    const Vec3f& p = c.positions[i];
    if (std::fabs(p.x) > 0.3f || p.y < 0.5f || p.y > 1.5f) continue;
    ++near_step;
    layered += std::isfinite(cut[i]);
  }
  EXPECT_GT(near_step, 50u);
  EXPECT_LE(layered, near_step / 50);
}

TEST(NormalsLayerCuts, OnlyTheLayeredPointsAreTried) {
  Cloud c;
  DeterministicRng rng(14);
  add_sheet(c, 0, 2, 0, 0, rng);
  add_sheet(c, 0, 2, 1.6f * kSpacing, 1, rng);
  const std::vector<uint32_t> rows = rows_of(c);
  std::vector<uint8_t> layered(c.positions.size(), 0);
  for (std::size_t i = 0; i < layered.size(); i += 2) layered[i] = 1;
  const std::vector<float> all = layer_cuts(c.positions, c.normals, rows, kOrientK - 1, {});
  const std::vector<float> some = layer_cuts(c.positions, c.normals, rows, kOrientK - 1, layered);
  for (std::size_t i = 0; i < layered.size(); ++i) {
    if (layered[i])
      EXPECT_TRUE(std::isfinite(all[i]) ? some[i] == all[i] : !std::isfinite(some[i])) << i;
    else
      EXPECT_FALSE(std::isfinite(some[i])) << i;
  }
}

}  // namespace
}  // namespace splatkit
