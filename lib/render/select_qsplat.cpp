#include "render/select_qsplat.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "formats/qsplat_codes.h"
#include "render/render_scene.h"

namespace splatkit::render {

namespace {

struct Draws {
  std::vector<Vec3f> positions, normals, colors;
  std::vector<float> radii;
};

struct Traversal {
  const QSplatModel& m;
  const Projection& proj;
  float threshold;
  float plane_x[2], plane_y[2];  // (a, b) of the side planes a·x − b·z = 0, normalised
  std::array<Vec3f, 65536> const* palette;

  // 0: culled by the frustum, 1: culled by the cone, 2: visible.
  int classify(uint32_t i, float& z) const {
    const Vec3f c = proj.to_camera(m.centres[i]);
    const float r = m.radii[i];
    z = c.z;
    if (c.z + r < proj.near) return 0;
    if (c.x * plane_x[0] - c.z * plane_x[1] > r || -c.x * plane_x[0] - c.z * plane_x[1] > r ||
        c.y * plane_y[0] - c.z * plane_y[1] > r || -c.y * plane_y[0] - c.z * plane_y[1] > r)
      return 0;
    const int cone = m.cones[i];
    if (cone < 3) {
      const Vec3f& n = qsplat::decode_normal(m.normal_codes[i]);
      const Vec3f v = proj.eye - m.centres[i];
      const float nv = dot(n, v);
      const float s = qsplat::decode_cone_sine(cone);
      const float lim = (norm(v) + r) * s;
      if (nv < -r && (nv + r) * (nv + r) > lim * lim) return 1;
    }
    return 2;
  }

  void draw(uint32_t i, Draws& out) const {
    out.positions.push_back(m.centres[i]);
    out.normals.push_back(qsplat::decode_normal(m.normal_codes[i]));
    out.radii.push_back(m.radii[i]);
    if (!m.colors.empty()) out.colors.push_back((*palette)[m.colors[i]]);
  }

  // Visits node i and what lies below it, appending to `out`. `defer`: nodes at depth `split`
  // below the start go to `deferred` (in order) instead of being visited.
  void visit(uint32_t i, Draws& out, LodStats& st, std::vector<uint32_t>* deferred, int depth,
             int split) const {
    std::vector<std::pair<uint32_t, int>> stack{{i, depth}};
    while (!stack.empty()) {
      const auto [n, d] = stack.back();
      stack.pop_back();
      ++st.visited;
      float z = 0;
      const int cls = m.child_count[n] && d == 0 ? 2 : classify(n, z);  // roots have no cone
      if (cls == 0) {
        ++st.culled_frustum;
        continue;
      }
      if (cls == 1) {
        ++st.culled_cone;
        continue;
      }
      const int kids = m.child_count[n];
      const bool small = z > proj.near && 2 * m.radii[n] * proj.focal_px / z <= threshold;
      if (kids == 0 || (small && d > 0)) {
        draw(n, out);
        continue;
      }
      if (deferred && d + 1 == split) {
        // Children become tasks, in order (the stack pops them in reverse below otherwise).
        for (int k = 0; k < kids; ++k) deferred->push_back(m.first_child[n] + k);
        continue;
      }
      for (int k = kids; k-- > 0;)
        stack.push_back({m.first_child[n] + static_cast<uint32_t>(k), d + 1});
    }
  }
};

const std::array<Vec3f, 65536>& linear_palette() {
  static const std::array<Vec3f, 65536> p = [] {
    float five[32], six[64];  // each channel's 8-bit expansion, made linear once
    for (int v = 0; v < 32; ++v) five[v] = srgb_to_linear(((v << 3) | (v >> 2)) / 255.0f);
    for (int v = 0; v < 64; ++v) six[v] = srgb_to_linear(((v << 2) | (v >> 4)) / 255.0f);
    std::array<Vec3f, 65536> t{};
    for (uint32_t w = 0; w < 65536; ++w) t[w] = {five[w >> 11], six[(w >> 5) & 63u], five[w & 31u]};
    return t;
  }();
  return p;
}

void append(Draws& to, Draws&& from) {
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  to.radii.insert(to.radii.end(), from.radii.begin(), from.radii.end());
  to.colors.insert(to.colors.end(), from.colors.begin(), from.colors.end());
}

}  // namespace

DrawList select_qsplat(const QSplatModel& m, const Projection& proj, float threshold_px,
                       LodStats* stats) {
  Traversal t{m, proj, threshold_px, {}, {}, &linear_palette()};
  const float tx = proj.cx / proj.focal_px, ty = proj.cy / proj.focal_px;
  const float nx = std::sqrt(1 + tx * tx), ny = std::sqrt(1 + ty * ty);
  t.plane_x[0] = 1 / nx;
  t.plane_x[1] = tx / nx;
  t.plane_y[0] = 1 / ny;
  t.plane_y[1] = ty / ny;
  // The top of each tree sequentially, down to a few hundred subtrees; those in parallel.
  LodStats total;
  auto all = std::make_shared<Draws>();
  for (uint32_t root : m.roots) {
    std::vector<uint32_t> tasks;
    t.visit(root, *all, total, &tasks, 0, 5);
    std::vector<Draws> parts(tasks.size());
    std::vector<LodStats> part_stats(tasks.size());
    tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t k) {
      t.visit(tasks[k], parts[k], part_stats[k], nullptr, 5, 0);
    });
    for (std::size_t k = 0; k < tasks.size(); ++k) {
      append(*all, std::move(parts[k]));
      total.visited += part_stats[k].visited;
      total.culled_frustum += part_stats[k].culled_frustum;
      total.culled_cone += part_stats[k].culled_cone;
    }
  }
  if (stats) *stats = total;
  DrawList d;
  d.count = all->positions.size();
  d.positions = all->positions.data();
  d.normals = all->normals.data();
  d.radii = all->radii.data();
  d.colors = all->colors.empty() ? nullptr : all->colors.data();
  d.storage = all;
  return d;
}

}  // namespace splatkit::render
