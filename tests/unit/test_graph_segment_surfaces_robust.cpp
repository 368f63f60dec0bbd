// segment_surfaces_robust: surfaces grown from core splats, so a band of gradually turning
// normals (a noisy crease) does not merge two faces; on clean normals the components.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "graph/build_splat_graph.h"
#include "graph/segment_surfaces_robust.h"
#include "normals/estimate_normals.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit::graph {
namespace {

// 30 splats on the x axis, each joined to those within 2 places. Normals: 0° (+z) up to splat 9,
// then turning 9° per splat to 90° (+x) at splat 19 and after: a smeared crease. Every edge turns
// by at most 18°, below the sharp angle of w_s = 0.9 (25.8°), so [IvoMSc]'s components are one.
struct Chain {
  NeighborGraph graph;
  std::vector<uint8_t> flags;
  std::vector<Vec3f> positions, normals;
};

Chain smeared_crease() {
  Chain c;
  for (int i = 0; i < 30; ++i) {
    const double a = std::clamp(i - 9, 0, 10) * 9.0 * std::numbers::pi / 180;
    c.positions.push_back({float(i), 0, 0});
    c.normals.push_back({float(std::sin(a)), 0, float(std::cos(a))});
  }
  c.graph.offsets.push_back(0);
  for (int i = 0; i < 30; ++i) {
    for (int j = std::max(0, i - 2); j <= std::min(29, i + 2); ++j) {
      if (j == i) continue;
      c.graph.neighbors.push_back(uint32_t(j));
      c.flags.push_back(dot(c.normals[i], c.normals[j]) < 0.9f ? 1 : 0);
    }
    c.graph.offsets.push_back(c.graph.neighbors.size());
  }
  return c;
}

RobustSegmentOptions fixed(float core, uint32_t min_core) {
  RobustSegmentOptions o;
  o.core_threshold = core;
  o.min_core_size = min_core;
  return o;
}

TEST(GraphSegmentSurfacesRobust, SmearedCreaseSplitsBetweenTheCores) {
  const Chain c = smeared_crease();
  ASSERT_EQ(segment_surfaces(c.graph, c.flags, 1).count(), 1u);  // the method of [IvoMSc] leaks
  // Cores at 12.9°: splats 0..8 and 20..29. Round by round the band is handed out from both
  // sides: 9, 10 from splat 7/8; 18, 19 from 20; then 11, 12; 16, 17; 13, 14; 15 (from 16).
  RobustSegmentInfo info;
  const Segmentation seg = segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals,
                                                   fixed(default_core_threshold(0.9f), 1), &info);
  std::vector<uint32_t> expected(30, 1);
  std::fill(expected.begin(), expected.begin() + 15, 0);
  EXPECT_EQ(seg.surface, expected);
  EXPECT_EQ(seg.sizes, (std::vector<uint32_t>{15, 15}));
  EXPECT_FLOAT_EQ(info.core_threshold, default_core_threshold(0.9f));
}

TEST(GraphSegmentSurfacesRobust, SmallCoreComponentsAreNotCores) {
  const Chain c = smeared_crease();
  // 0..8 is a core component of 9 splats: below 10 it is not a core, and 20..29 takes all.
  const Segmentation seg = segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals,
                                                   fixed(default_core_threshold(0.9f), 10));
  EXPECT_EQ(seg.surface, std::vector<uint32_t>(30, 0));
  // No core at all (threshold 1 but the normals differ): the components.
  const Segmentation none =
      segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals, fixed(1.0f, 100));
  EXPECT_EQ(none.surface, std::vector<uint32_t>(30, 0));
}

TEST(GraphSegmentSurfacesRobust, AutomaticThresholdSeesTheNoise) {
  const Chain c = smeared_crease();
  // Exact, smoothly turning normals: no noise, so the core threshold is w_s and the result the
  // components.
  RobustSegmentInfo info;
  RobustSegmentOptions o;
  o.min_core_size = 1;
  EXPECT_EQ(segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals, o, &info).count(),
            1u);
  EXPECT_LT(info.normal_noise_degrees, 0.75);
  EXPECT_FLOAT_EQ(info.core_threshold, 0.9f);
}

TEST(GraphSegmentSurfacesRobust, DefaultCoreThresholdIsHalfTheSharpAngle) {
  EXPECT_NEAR(std::acos(default_core_threshold(0.9f)), std::acos(0.9) / 2, 1e-6);
  EXPECT_NEAR(default_core_threshold(-1.0f), std::cos(std::numbers::pi / 2), 1e-6);
  EXPECT_FLOAT_EQ(default_core_threshold(1.0f), 1.0f);
}

// Clean normals from the generator: exactly the components. The CAD part with the automatic
// threshold (no noise: w_s); two spheres that cross each other and a cube also with the core
// angle at 12.9° — sharp neighbours do not count against a core, so a sphere is not cut along
// the intersection circle. (The CAD part's hole, 6000 splats, turns by more than 12.9° between
// neighbours: with that threshold forced it would fall apart, which is why clean normals get w_s.)
TEST(GraphSegmentSurfacesRobust, CleanShapesGiveTheComponents) {
  for (const auto& [kind, keep_inside] :
       {std::pair{ShapeKind::kCadPart, false}, std::pair{ShapeKind::kTwoSpheres, true},
        std::pair{ShapeKind::kCube, false}}) {
    ShapeOptions so;
    so.kind = kind;
    so.points = 6000;
    so.keep_inside = keep_inside;
    const SplatCloud cloud = make_shape(so);
    SplatGraphOptions go;
    go.robust_surfaces = false;
    const SplatGraph g = build_splat_graph(cloud, go);
    RobustSegmentOptions automatic;
    RobustSegmentInfo info;
    EXPECT_EQ(segment_surfaces_robust(g.graph, g.edge_flags, kEdgeSharp, cloud.positions,
                                      cloud.normals, automatic, &info)
                  .surface,
              g.surfaces.surface)
        << shape_kind_name(kind);
    EXPECT_LT(info.normal_noise_degrees, 0.75) << shape_kind_name(kind);
    if (kind == ShapeKind::kCadPart) continue;
    const Segmentation seg =
        segment_surfaces_robust(g.graph, g.edge_flags, kEdgeSharp, cloud.positions, cloud.normals,
                                fixed(default_core_threshold(0.9f), 10));
    EXPECT_EQ(seg.surface, g.surfaces.surface) << shape_kind_name(kind);
    EXPECT_EQ(seg.count(), kind == ShapeKind::kCube ? 6u : 2u) << shape_kind_name(kind);
  }
}

// PCA normals of clean scans: exact on the faces (no noise) but blended from face to face across
// every crease, so the components run across them; the automatic threshold sees that from the
// sharp edges inside the components and takes the core angle, which gives every patch its own
// surface. Random and scan-line samplings, the default estimate-normals options.
TEST(GraphSegmentSurfacesRobust, CleanPcaNormalsDoNotMergeTheFaces) {
  struct Case {
    ShapeKind kind;
    double scan_lines;
    uint32_t patches;
  };
  for (const Case& k : {Case{ShapeKind::kCube, 0, 6}, Case{ShapeKind::kCube, 8, 6},
                        Case{ShapeKind::kCadPart, 0, 9}}) {
    ShapeOptions so;
    so.kind = k.kind;
    so.points = 40000;
    so.random = true;
    so.scan_lines = k.scan_lines;
    SplatCloud cloud = make_shape(so);
    estimate_normals(cloud, NormalOptions{});
    const ExtraAttribute* patch_id = cloud.find_extra("patch_id");
    ASSERT_NE(patch_id, nullptr);
    const std::vector<double> patch = patch_id->values.doubles();
    SplatGraphOptions go;
    go.robust_surfaces = false;
    const SplatGraph g = build_splat_graph(cloud, go);
    const std::string name =
        std::string(shape_kind_name(k.kind)) + (k.scan_lines > 0 ? " scan lines" : " random");
    RobustSegmentInfo info;
    const Segmentation seg = segment_surfaces_robust(g.graph, g.edge_flags, kEdgeSharp,
                                                     cloud.positions, cloud.normals, {}, &info);
    // The components merge the faces (what the automatic choice guards against): one of them
    // holds more than half the splats.
    std::vector<uint32_t> component_size(g.surfaces.count(), 0);
    for (uint32_t c : g.surfaces.surface) ++component_size[c];
    EXPECT_GT(*std::max_element(component_size.begin(), component_size.end()),
              cloud.size() / 2)
        << name;
    EXPECT_LT(info.normal_noise_degrees, 0.75) << name;
    EXPECT_GE(info.sharp_edges_within, 0.5) << name;
    EXPECT_FLOAT_EQ(info.core_threshold, default_core_threshold(0.9f)) << name;
    // Every patch's splats mostly in one surface of their own.
    std::vector<std::vector<uint32_t>> count(k.patches, std::vector<uint32_t>(seg.count(), 0));
    for (std::size_t i = 0; i < patch.size(); ++i) ++count[std::size_t(patch[i])][seg.surface[i]];
    std::vector<uint32_t> owner(k.patches);
    for (uint32_t p = 0; p < k.patches; ++p) {
      owner[p] = uint32_t(std::max_element(count[p].begin(), count[p].end()) - count[p].begin());
      const uint32_t total = std::accumulate(count[p].begin(), count[p].end(), 0u);
      EXPECT_GE(count[p][owner[p]], 0.9 * total) << name << " patch " << p;
    }
    std::sort(owner.begin(), owner.end());
    EXPECT_EQ(std::unique(owner.begin(), owner.end()) - owner.begin(), k.patches) << name;
  }
}

TEST(GraphSegmentSurfacesRobust, NanNormalIsNotACoreAndSizesAreChecked) {
  Chain c = smeared_crease();
  c.normals[3] = {std::numeric_limits<float>::quiet_NaN(), 0, 1};
  for (uint64_t k = 0; k < c.graph.neighbors.size(); ++k) c.flags[k] = 0;
  // Splat 3 is no core, but 0..29 stay one surface through the others (threshold -1: all edges
  // agree except with the NaN).
  const Segmentation seg =
      segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals, fixed(-1.0f, 1));
  EXPECT_EQ(seg.count(), 1u);
  EXPECT_THROW(segment_surfaces_robust(c.graph, c.flags, 1, c.positions,
                                       std::span(c.normals).first(29), fixed(-1.0f, 1)),
               std::invalid_argument);
  EXPECT_THROW(segment_surfaces_robust(c.graph, std::span(c.flags).first(3), 1, c.positions,
                                       c.normals, fixed(-1.0f, 1)),
               std::invalid_argument);
  EXPECT_THROW(
      segment_surfaces_robust(c.graph, c.flags, 1, c.positions, c.normals, fixed(-1.0f, 0)),
      std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
