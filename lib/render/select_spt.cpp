#include "render/select_spt.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "render/render_scene.h"

namespace splatkit::render {

namespace {

struct Draws {
  std::vector<Vec3f> positions, normals, colors;
  std::vector<float> radii;
};

const std::array<Vec3f, 256>& linear_table() {
  static const std::array<Vec3f, 256> t = [] {
    std::array<Vec3f, 256> out{};
    for (int v = 0; v < 256; ++v) {
      const float l = srgb_to_linear(v / 255.0f);
      out[v] = {l, l, l};
    }
    return out;
  }();
  return t;
}

// The view distance -> stored r factor and the length of the prefix the test can pass.
struct Prefix {
  float k;
  std::size_t length;
};

Prefix find_prefix(const SptModel& m, const BoundingSphere& bounds, const Projection& proj,
                   float error_px) {
  const float k = error_px / proj.focal_px / m.header.epsilon;  // view distance -> stored r
  const float nearest = std::max(0.0f, norm(proj.eye - bounds.center) - bounds.radius) * k;
  return {k, static_cast<std::size_t>(std::partition_point(m.r_max.begin(), m.r_max.end(),
                                                           [&](float r) { return r > nearest; }) -
                                      m.r_max.begin())};
}

constexpr std::size_t kChunk = 1 << 15;  // prefix entries per task

}  // namespace

Vec3f spt_linear_color(const std::array<uint8_t, 3>& rgb) {
  const auto& table = linear_table();
  return {table[rgb[0]].x, table[rgb[1]].x, table[rgb[2]].x};
}

SptZBufferCounts draw_spt_zbuffer(const SptModel& m, const BoundingSphere& bounds,
                                  const Projection& proj, float error_px,
                                  DepthKeyBuffer& buffer) {
  const Prefix found = find_prefix(m, bounds, proj, error_px);
  const float k = found.k;  // named copies: clang 14 lambdas cannot capture structured bindings
  const std::size_t prefix = found.length;
  struct Counts {
    uint64_t selected = 0, drawn = 0;
  };
  const Counts c = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, prefix, kChunk), Counts{},
      [&](const auto& range, Counts acc) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const float r = norm(m.positions[i] - proj.eye) * k;
          if (!(m.r_min[i] <= r && r < m.r_max[i])) continue;
          ++acc.selected;
          acc.drawn += zbuffer_splat(buffer, proj, proj.to_camera(m.positions[i]),
                                     0.5f * m.diameters[i], static_cast<uint32_t>(i));
        }
        return acc;
      },
      [](Counts a, const Counts& b) { return Counts{a.selected + b.selected, a.drawn + b.drawn}; });
  return {prefix, c.selected, c.drawn};
}

DrawList select_spt(const SptModel& m, const BoundingSphere& bounds, const Projection& proj,
                    float error_px, LodStats* stats) {
  const Prefix found = find_prefix(m, bounds, proj, error_px);
  const float k = found.k;  // named copies: clang 14 lambdas cannot capture structured bindings
  const std::size_t prefix = found.length;
  // Chunks of the prefix tested in parallel; each keeps the indices it draws, in order.
  const std::size_t chunks = (prefix + kChunk - 1) / kChunk;
  std::vector<std::vector<uint32_t>> picked(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    const std::size_t b = c * kChunk, e = std::min(prefix, b + kChunk);
    std::vector<uint32_t>& out = picked[c];
    out.reserve(e - b);
    for (std::size_t i = b; i < e; ++i) {
      const float r = norm(m.positions[i] - proj.eye) * k;
      if (m.r_min[i] <= r && r < m.r_max[i]) out.push_back(static_cast<uint32_t>(i));
    }
  });
  std::vector<std::size_t> start(chunks + 1, 0);
  for (std::size_t c = 0; c < chunks; ++c) start[c + 1] = start[c] + picked[c].size();
  const std::size_t count = start.back();
  auto all = std::make_shared<Draws>();
  all->positions.resize(count);
  all->normals.resize(count);
  all->radii.resize(count);
  if (!m.colors.empty()) all->colors.resize(count);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::size_t j = start[c];
    for (uint32_t i : picked[c]) {
      all->positions[j] = m.positions[i];
      all->normals[j] = m.normals[i];
      all->radii[j] = 0.5f * m.diameters[i];
      if (!m.colors.empty()) all->colors[j] = spt_linear_color(m.colors[i]);
      ++j;
    }
  });
  if (stats) {
    *stats = {};
    stats->spt_prefix = prefix;
    stats->spt_culled = prefix - count;
  }
  DrawList d;
  d.count = count;
  d.positions = all->positions.data();
  d.normals = all->normals.data();
  d.radii = all->radii.data();
  d.colors = all->colors.empty() ? nullptr : all->colors.data();
  d.storage = all;
  return d;
}

}  // namespace splatkit::render
