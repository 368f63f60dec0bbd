#include "render/select_spt.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>

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

// CPU time of the calling thread (the machine may be shared: wall time includes waiting).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

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
  const float point_radius_px = 0.5f * kSptPointDiameterPx;
  const Vec3f* positions = m.positions.data();
  const float* r_min = m.r_min.data();
  const float* r_max = m.r_max.data();
  const float* diameters = m.diameters.data();
  const Vec3f* normals = m.normals.data();
  const SptZBufferCounts c = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, prefix, kChunk), SptZBufferCounts{},
      [&](const auto& range, SptZBufferCounts acc) {
        const double cpu0 = thread_cpu_seconds();
        const Projection p = proj;  // a local copy: the stores into the buffer cannot alias it
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const Vec3f d = positions[i] - p.eye;
          const float r = norm(d) * k;
          if (!(r_min[i] <= r && r < r_max[i])) continue;
          ++acc.selected;
          const Vec3f cam{dot(d, p.right), dot(d, p.down), dot(d, p.forward)};  // to_camera
          const float radius = 0.5f * diameters[i];
          if (!(cam.z - radius >= p.near)) continue;  // as zbuffer_splat: not drawn
          const float inv = 1.0f / cam.z;
          const float rp = p.focal_px * radius * inv;
          bool drawn;
          if (rp <= point_radius_px) {
            drawn = zbuffer_point(buffer, p.cx + p.focal_px * cam.x * inv,
                                  p.cy + p.focal_px * cam.y * inv, cam.z, static_cast<uint32_t>(i));
            acc.points += drawn;
          } else {
            drawn = zbuffer_disc(
                buffer, p, cam, [&] { return camera_direction(p, normals[i]); }, radius,
                static_cast<uint32_t>(i));
          }
          acc.drawn += drawn;
          if (drawn) acc.diameter_px_sum += 2 * rp;
        }
        acc.cpu_s += thread_cpu_seconds() - cpu0;
        return acc;
      },
      [](SptZBufferCounts a, const SptZBufferCounts& b) {
        a.selected += b.selected;
        a.drawn += b.drawn;
        a.points += b.points;
        a.diameter_px_sum += b.diameter_px_sum;
        a.cpu_s += b.cpu_s;
        return a;
      });
  SptZBufferCounts out = c;
  out.prefix = prefix;
  return out;
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
