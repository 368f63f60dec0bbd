// The splats estimate-normals makes cover the surface they were sampled from, on clouds sampled as
// scanners sample: i.i.d. random, with noise, along scan lines (splat_coverage.h measures it at
// fresh points of the exact surface). Also the measure itself on hand-made splats.
#include "normals/splat_coverage.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <tuple>
#include <vector>

#include "normals/estimate_normals.h"
#include "splatkit/synthetic_shapes.h"

namespace splatkit {
namespace {

struct Case {
  const char* name;
  ShapeKind kind;
  double noise;
  double scan_lines;
  NormalOptions options;
};

NormalOptions with(NormalMethod method, bool fit_centres, bool ellipses = false) {
  NormalOptions o;
  o.method = method;
  o.fit_centres = fit_centres;
  o.ellipses = ellipses;
  return o;
}

// Splats of a 100k-point sample of `c`, measured at 100k fresh points of the exact surface.
SplatCoverage coverage_of(const Case& c) {
  ShapeOptions sample;
  sample.kind = c.kind;
  sample.points = 100000;
  sample.random = true;
  sample.noise = c.noise;
  sample.scan_lines = c.scan_lines;
  sample.seed = 7;
  SplatCloud cloud = make_shape(sample);
  estimate_normals(cloud, c.options);
  ShapeOptions truth;
  truth.kind = c.kind;
  truth.points = 100000;
  truth.random = true;
  truth.seed = 1234;
  const SplatCloud surface = make_shape(truth);
  const SplatCoverage cov = splat_coverage(cloud, surface.positions);
  std::printf("%-34s uncovered %.4f %%, mean splats per surface point %.2f\n", c.name,
              100 * cov.uncovered_fraction(), cov.mean_splats);
  return cov;
}

// The goal on i.i.d. samples: at most 0.01 % of the surface uncovered, at most 4 splats over a
// surface point on average.
void expect_covered(const Case& c) {
  SCOPED_TRACE(c.name);
  const SplatCoverage cov = coverage_of(c);
  EXPECT_LE(cov.uncovered_fraction(), 1e-4);
  EXPECT_LE(cov.mean_splats, 4.0);
}

constexpr auto kPca = NormalMethod::kPca;
constexpr auto kRobust = NormalMethod::kRobust;

TEST(NormalsSplatCoverage, CoverRadiiLeaveNoHoleOnRandomSamples) {
  const Case cases[] = {
      {"random sphere", ShapeKind::kSphere, 0, 0, with(kPca, false)},
      {"random torus", ShapeKind::kTorus, 0, 0, with(kPca, false)},
      {"random sphere, noise, fit centres", ShapeKind::kSphere, 0.00125, 0, with(kPca, true)},
      {"random torus, noise, fit centres", ShapeKind::kTorus, 0.00125, 0, with(kPca, true)},
  };
  for (const Case& c : cases) expect_covered(c);
}

// The CAD part's creases: the splats of each face reach the crease, as neighbours across it
// (another sheet, told apart by their normals) do not bound their cells.
TEST(NormalsSplatCoverage, CadPartCoveredUpToItsCreases) {
  const Case cases[] = {
      {"random cad, robust", ShapeKind::kCadPart, 0, 0, with(kRobust, false)},
      {"random cad, noise, robust, fit centres", ShapeKind::kCadPart, 0.00125, 0,
       with(kRobust, true)},
  };
  for (const Case& c : cases) expect_covered(c);
}

TEST(NormalsSplatCoverage, MeanKnnRadiiLeaveHoles) {
  Case c{"random sphere, mean-knn", ShapeKind::kSphere, 0, 0, {}};
  c.options.radius_rule = RadiusRule::kMeanKnn;
  EXPECT_GT(coverage_of(c).uncovered_fraction(), 0.01);  // the rule's known weakness, ~2.5 %
}

// Scan lines 4× denser along than across: ellipses cover about as well as circles with at least
// 30 % fewer splats over each surface point (measured: sphere 0.000 % for both; CAD part 0.003 %
// circles, 0.010 % ellipses, the last lines before its creases).
TEST(NormalsSplatCoverage, EllipsesCoverScanLinesWithLessOverdraw) {
  for (auto [name, kind, method] : {std::tuple{"sphere", ShapeKind::kSphere, kPca},
                                    std::tuple{"cad", ShapeKind::kCadPart, kRobust}}) {
    SCOPED_TRACE(name);
    const Case circles{"scan lines 4:1, circles", kind, 0, 4, with(method, false)};
    const Case ellipses{"scan lines 4:1, ellipses", kind, 0, 4, with(method, false, true)};
    const SplatCoverage a = coverage_of(circles), b = coverage_of(ellipses);
    EXPECT_LE(a.uncovered_fraction(), 1e-4);
    EXPECT_LE(b.uncovered_fraction(), 2e-4);
    EXPECT_LE(b.mean_splats, 0.7 * a.mean_splats);
  }
}

}  // namespace
}  // namespace splatkit
