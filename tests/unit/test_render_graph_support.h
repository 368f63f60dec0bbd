// Test support for rendering with the splat graph (clipping, surface ids): a synthetic shape
// with its true normals and generator radii, the graph of build_splat_graph, a render scene with
// its clip partners and surface ids; a reference image ray cast against the exact shape (sphere
// tracing its distance function) labelled with the true patch per pixel; and the image measures
// the tests assert (per-pixel patch errors, holes, overhangs, edge transition widths).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "graph/build_splat_graph.h"
#include "render/camera.h"
#include "render/frame_renderer.h"
#include "render/render_scene.h"
#include "splatkit/synthetic_shapes.h"
#include "test_render_support.h"

namespace splatkit::render::testing {

struct GraphScene {
  ShapeOptions shape;
  RenderScene scene;                       // with clip partners and surface ids from the graph
  std::vector<uint32_t> patch;             // #N true patch of each splat (patch_id)
  std::vector<uint32_t> patch_of_surface;  // majority true patch of each surface id
  graph::SplatGraphStats stats;
};

inline GraphScene make_graph_scene(const ShapeOptions& shape) {
  GraphScene g;
  g.shape = shape;
  SplatCloud cloud = make_shape(shape);
  const graph::SplatGraph graph = graph::build_splat_graph(cloud, graph::SplatGraphOptions{});
  g.stats = graph.stats;
  const ExtraAttribute* patch = cloud.find_extra("patch_id");
  const std::vector<double> ids = patch->values.doubles();
  g.patch.assign(ids.begin(), ids.end());
  g.scene = make_render_scene(std::move(cloud), "test");
  g.scene.surface_ids = graph.surfaces.surface;
  attach_clip_partners(g.scene, graph.clip, "test");
  std::vector<std::map<uint32_t, uint32_t>> votes(graph.surfaces.count());
  for (std::size_t i = 0; i < g.patch.size(); ++i) ++votes[g.scene.surface_ids[i]][g.patch[i]];
  for (const auto& v : votes)
    g.patch_of_surface.push_back(std::max_element(v.begin(), v.end(), [](auto& a, auto& b) {
                                   return a.second < b.second;
                                 })->first);
  return g;
}

inline constexpr uint32_t kNoPatch = 0xFFFFFFFFu;

// The true patch seen through each pixel centre (kNoPatch: background), by sphere tracing the
// exact distance function of the shape (unsigned distance: steps never pass the surface).
inline std::vector<uint32_t> reference_patches(const ShapeOptions& shape, const Camera& camera) {
  const Projection pr = make_projection(camera);
  const uint32_t patches = static_cast<uint32_t>(shape_patch_names(shape).size());
  const Bounds b = shape_bounds(shape);
  const float far = norm(pr.eye - (b.min + b.max) * 0.5f) + norm(b.max - b.min);
  std::vector<uint32_t> out(std::size_t(camera.width) * camera.height, kNoPatch);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Vec3f d = normalized(pr.ray(x + 0.5f, y + 0.5f));
      float t = 0;
      for (int k = 0; k < 2000 && t < far; ++k) {
        const Vec3f p = pr.eye + d * t;
        const float dist = distance_to_shape(shape, p);
        if (dist < 1e-5f) {
          uint32_t best = 0;
          float best_d = 1e30f;
          for (uint32_t q = 0; q < patches; ++q) {
            const float dq = distance_to_patch(shape, q, p);
            if (dq < best_d) best_d = dq, best = q;
          }
          out[std::size_t(y) * camera.width + x] = best;
          break;
        }
        t += std::max(dist, 1e-6f);
      }
    }
  return out;
}

// The true patch each rendered pixel shows (via its surface id), kNoPatch where nothing is
// drawn. Needs the surface id plane.
inline std::vector<uint32_t> rendered_patches(const GraphScene& g, const Framebuffer& fb) {
  std::vector<uint32_t> out(fb.alpha.size(), kNoPatch);
  for (std::size_t p = 0; p < out.size(); ++p)
    if (fb.alpha[p] > 0) out[p] = g.patch_of_surface.at(fb.surface_id[p]);
  return out;
}

struct PatchErrors {
  int compared = 0;  // reference pixels whose 3×3 neighbourhood shows one patch (or background)
  int wrong = 0;     // drawn, but another patch than the reference
  int holes = 0;     // reference has a surface, nothing drawn
  int outside = 0;   // drawn where the reference has background
};

// Compares away from the reference's patch boundaries and silhouettes (1-pixel band), where a
// pixel centre's label is a matter of sub-pixel position.
inline PatchErrors compare_patches(const std::vector<uint32_t>& ref,
                                   const std::vector<uint32_t>& got, int w, int h) {
  PatchErrors e;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      bool uniform = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) uniform = uniform && ref[p + dy * w + dx] == ref[p];
      if (!uniform) continue;
      ++e.compared;
      if (ref[p] == kNoPatch) {
        e.outside += got[p] != kNoPatch;
      } else if (got[p] == kNoPatch) {
        ++e.holes;
      } else {
        e.wrong += got[p] != ref[p];
      }
    }
  return e;
}

// Pixel coordinates of a scene point.
inline Vec3f project(const Projection& pr, const Vec3f& p) {
  const Vec3f c = pr.to_camera(p);
  return {pr.cx + pr.focal_px * c.x / c.z, pr.cy + pr.focal_px * c.y / c.z, c.z};
}

struct EdgeProfile {
  double width_10_90 = 0;  // pixels, across the edge
  double centre = 0;       // 50 % crossing, pixels from the projected edge (+ towards face a)
  int background = 0;      // samples within 2 px of the edge that hit no surface
  int samples = 0;
};

// The mean profile of q = (n·n_a − n_b·n_a) / (1 − n_b·n_a) (1 on plane face a, 0 on plane face
// b) across the projected 3D edge p0–p1 (middle 70 %), sampled with nearest pixels at
// quarter-pixel steps along image-space perpendiculars; `into_a`: a scene direction from the edge
// into face a. Needs the normal and alpha AOVs.
inline EdgeProfile edge_profile(const Framebuffer& fb, const Projection& pr, const Vec3f& p0,
                                const Vec3f& p1, const Vec3f& n_a, const Vec3f& n_b,
                                const Vec3f& into_a) {
  const double q_b = dot(n_b, n_a);
  constexpr double kStep = 0.25, kReach = 8;
  const int bins = static_cast<int>(2 * kReach / kStep) + 1;
  std::vector<double> sum(bins, 0.0);
  std::vector<int> count(bins, 0);
  EdgeProfile out;
  const Vec3f a = project(pr, p0), b = project(pr, p1);
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  for (double s = 0.15 * len; s <= 0.85 * len; s += 0.5) {
    const double t = s / len;
    const Vec3f p = p0 + (p1 - p0) * static_cast<float>(t);
    const Vec3f c = project(pr, p), ca = project(pr, p + into_a * 0.01f);
    double ex = (b.x - a.x) / len, ey = (b.y - a.y) / len;
    double px = -ey, py = ex;
    if ((ca.x - c.x) * px + (ca.y - c.y) * py < 0) px = -px, py = -py;
    for (int k = 0; k < bins; ++k) {
      const double o = -kReach + k * kStep;
      const int x = static_cast<int>(std::floor(c.x + o * px));
      const int y = static_cast<int>(std::floor(c.y + o * py));
      if (x < 0 || y < 0 || x >= fb.width || y >= fb.height) continue;
      const std::size_t q = std::size_t(y) * fb.width + x;
      if (fb.alpha[q] == 0) {
        out.background += std::fabs(o) <= 2;
        continue;
      }
      const Vec3f n{fb.normal[3 * q], fb.normal[3 * q + 1], fb.normal[3 * q + 2]};
      sum[k] += std::clamp<double>((dot(n, n_a) - q_b) / (1 - q_b), 0.0, 1.0);
      ++count[k];
    }
    ++out.samples;
  }
  std::vector<double> mean(bins);
  for (int k = 0; k < bins; ++k) mean[k] = count[k] ? sum[k] / count[k] : 0.0;
  // First crossing of a level from the b side (left), and from the a side (right), with linear
  // interpolation between bins.
  auto from_left = [&](double level) {
    for (int k = 1; k < bins; ++k)
      if (mean[k] >= level)
        return -kReach + (k - 1 + (level - mean[k - 1]) / (mean[k] - mean[k - 1])) * kStep;
    return kReach;
  };
  auto from_right = [&](double level) {
    for (int k = bins - 2; k >= 0; --k)
      if (mean[k] <= level)
        return -kReach + (k + (level - mean[k]) / (mean[k + 1] - mean[k])) * kStep;
    return -kReach;
  };
  out.width_10_90 = from_right(0.9) - from_left(0.1);
  out.centre = 0.5 * (from_left(0.5) + from_right(0.5));
  return out;
}

// <name>.ppm, the 8-bit colour plane (dump_ppm).
inline void dump_rgb8(const std::string& name, const Framebuffer& fb) {
  if (!fb.rgb8.empty())
    dump_ppm(name + ".ppm", fb.width, fb.height, [&](std::size_t i) { return fb.rgb8[i]; });
}

}  // namespace splatkit::render::testing
