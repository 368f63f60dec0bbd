#include "render/select_spt.h"

#include <tbb/parallel_for.h>

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

}  // namespace

DrawList select_spt(const SptModel& m, const BoundingSphere& bounds, const Projection& proj,
                    float error_px, LodStats* stats) {
  const float k = error_px / proj.focal_px / m.header.epsilon;  // view distance -> stored r
  const float nearest = std::max(0.0f, norm(proj.eye - bounds.center) - bounds.radius) * k;
  const std::size_t prefix = static_cast<std::size_t>(
      std::partition_point(m.r_max.begin(), m.r_max.end(), [&](float r) { return r > nearest; }) -
      m.r_max.begin());
  // Chunks of the prefix tested in parallel; each keeps the indices it draws, in order.
  constexpr std::size_t kChunk = 1 << 15;
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
  const auto& table = linear_table();
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::size_t j = start[c];
    for (uint32_t i : picked[c]) {
      all->positions[j] = m.positions[i];
      all->normals[j] = m.normals[i];
      all->radii[j] = 0.5f * m.diameters[i];
      if (!m.colors.empty()) {
        const auto& rgb = m.colors[i];
        all->colors[j] = {table[rgb[0]].x, table[rgb[1]].x, table[rgb[2]].x};
      }
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
