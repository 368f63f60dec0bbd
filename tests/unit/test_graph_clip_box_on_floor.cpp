// The whole clip pipeline (build_splat_graph + clip record + fragment test) on a scene with
// convex and mixed corners: a box [-1, 1]² × [0, 2] standing on the floor z = 0. Every splat
// disc is sampled; a sample is wrong if it is kept but lies off the true surface (in the air:
// visible overhang; inside the solid: hidden) or is discarded although it lies on the surface
// away from any crease (a hole).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "graph/build_splat_graph.h"
#include "graph/make_clip_planes.h"

namespace splatkit::graph {
namespace {

constexpr float kStep = 0.25f;

struct Scene {
  std::vector<Vec3f> positions, normals;
  std::vector<float> radii;
  float jitter = 0, radius = 0.75f;  // in grid steps
  uint32_t rng = 12345;

  float next() {  // uniform in [-0.5, 0.5), a fixed LCG so the scene is the same everywhere
    rng = rng * 1664525u + 1013904223u;
    return static_cast<float>(rng >> 8) / float(1 << 24) - 0.5f;
  }
  void grid(const Vec3f& o, const Vec3f& a, const Vec3f& b, int na, int nb, const Vec3f& n,
            bool skip_footprint = false) {
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < na; ++i) {
        const float ja = jitter * next(), jb = jitter * next();
        const Vec3f p = o + a * ((i + 0.5f + ja) * kStep) + b * ((j + 0.5f + jb) * kStep);
        if (skip_footprint && std::abs(p.x) < 1 && std::abs(p.y) < 1) continue;
        positions.push_back(p);
        normals.push_back(n);
        radii.push_back(radius * kStep);
      }
  }
};

Scene box_on_floor(float jitter, float radius) {
  Scene s;
  s.jitter = jitter;
  s.radius = radius;
  s.grid({-3, -3, 0}, {1, 0, 0}, {0, 1, 0}, 24, 24, {0, 0, 1}, true);  // floor
  s.grid({1, -1, 0}, {0, 1, 0}, {0, 0, 1}, 8, 8, {1, 0, 0});
  s.grid({-1, -1, 0}, {0, 1, 0}, {0, 0, 1}, 8, 8, {-1, 0, 0});
  s.grid({-1, 1, 0}, {1, 0, 0}, {0, 0, 1}, 8, 8, {0, 1, 0});
  s.grid({-1, -1, 0}, {1, 0, 0}, {0, 0, 1}, 8, 8, {0, -1, 0});
  s.grid({-1, -1, 2}, {1, 0, 0}, {0, 1, 0}, 8, 8, {0, 0, 1});  // top
  return s;
}

// Signed distance to the solid: the box (reaching down into the floor slab) ∪ {z <= 0}.
float sdf(const Vec3f& p) {
  const Vec3f q{std::abs(p.x) - 1, std::abs(p.y) - 1, std::abs(p.z + 4) - 6};
  const Vec3f out{std::max(q.x, 0.f), std::max(q.y, 0.f), std::max(q.z, 0.f)};
  const float box = norm(out) + std::min(std::max({q.x, q.y, q.z}), 0.f);
  return std::min(box, p.z);
}

struct Errors {
  long kept_in_air = 0, kept_hidden = 0, holes = 0, off_surface = 0;
};

Errors sample_discs(const Scene& s, bool per_surface, bool clip = true) {
  SplatGraphOptions o;
  o.per_surface = per_surface;
  const SplatGraph g = build_splat_graph(s.positions, s.normals, s.radii, o);
  const auto planes = make_clip_planes(g.clip, s.positions, s.normals);
  Errors e;
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3f n = s.normals[i];
    const Vec3f a = normalized(cross(n, std::abs(n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    const Vec3f b = cross(n, a);
    const ClipView view = clip_view(g.clip, planes, i);
    for (int ri = 1; ri <= 8; ++ri)
      for (int ai = 0; ai < 32; ++ai) {
        const double t = (ai + 0.5) * 2 * std::numbers::pi / 32;
        const float r = s.radii[i] * ri / 8;
        const Vec3f p =
            s.positions[i] + a * (r * float(std::cos(t))) + b * (r * float(std::sin(t)));
        const bool discard = clip && fragment_discarded(view, p);
        const float d = sdf(p);
        if (std::abs(d) > 1e-4f) {
          ++e.off_surface;
          if (!discard) ++(d > 0 ? e.kept_in_air : e.kept_hidden);
          continue;
        }
        // On the surface; a discard there is a hole unless the sample sits on a crease.
        bool deep = true;
        for (const Vec3f& step : {a * 2e-3f, a * -2e-3f, b * 2e-3f, b * -2e-3f})
          deep = deep && std::abs(sdf(p + step)) < 1e-4f;
        if (discard && deep) ++e.holes;
      }
  }
  return e;
}

TEST(GraphClipBoxOnFloor, RegularSamplingIsExactPerSurface) {
  const Scene s = box_on_floor(0, 0.75f);
  const Errors none = sample_discs(s, true, false);
  EXPECT_EQ(none.kept_in_air, 2560);  // unclipped: every off-surface sample stays
  const Errors per_surface = sample_discs(s, true);
  EXPECT_EQ(per_surface.off_surface, 3840);
  EXPECT_EQ(per_surface.kept_in_air, 0);
  EXPECT_EQ(per_surface.kept_hidden, 0);
  EXPECT_EQ(per_surface.holes, 0);
  // [IvoMSc]'s single set fails at the four mixed corners at the box's foot.
  const Errors seed = sample_discs(s, false);
  EXPECT_EQ(seed.kept_hidden, 160);
}

TEST(GraphClipBoxOnFloor, JitteredSamplingPerSurfaceHasNoVisibleErrors) {
  for (const auto& [jitter, radius] : {std::pair{0.5f, 1.0f}, {0.5f, 1.3f}, {0.8f, 1.2f}}) {
    const Scene s = box_on_floor(jitter, radius);
    const Errors e = sample_discs(s, true);
    EXPECT_EQ(e.kept_in_air, 0) << jitter << " " << radius;
    EXPECT_EQ(e.holes, 0) << jitter << " " << radius;
    // Floor splats at the box's outer corners see a 270° ring of floor: Linsen calls them
    // intersections and they keep a sliver inside the box, hidden by its faces.
    EXPECT_LT(e.kept_hidden, e.off_surface / 200);
    const Errors seed = sample_discs(s, false);
    EXPECT_GT(seed.kept_in_air, 100) << jitter << " " << radius;
    EXPECT_GT(seed.holes, 100) << jitter << " " << radius;
  }
}

}  // namespace
}  // namespace splatkit::graph
