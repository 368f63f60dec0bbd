#include "render/select_qsplat.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "formats/qsplat_codes.h"
#include "formats/rgb565.h"
#include "render/render_scene.h"
#include "render/zbuffer_splats.h"

namespace splatkit::render {

namespace {

struct Draws {
  std::vector<Vec3f> positions, normals, colors;
  std::vector<float> radii;
};

// A subtree to visit, with what its ancestors proved (Traversal::classify).
struct Task {
  uint32_t node;
  uint8_t proved;
};

struct Traversal {
  const QSplatModel& m;
  const Projection& proj;
  float threshold;
  bool cull_backfaces;  // test the normal cones
  float plane_x[2], plane_y[2];  // (a, b) of the side planes a·x − b·z = 0, normalised

  // What a node's sphere proves for every sphere below it (each decoded child sphere lies inside
  // its decoded parent, and each child's normal cone inside its parent's), so that their tests
  // can be skipped: wholly inside the frustum, wholly front-facing. Both are proved with a small
  // margin, so that rounding never lets a skipped test differ from the one it stands for.
  enum : uint8_t { kInside = 1, kFront = 2 };

  // 0: culled by the frustum, 1: culled by the cone, 2: visible. `c` gets the centre in camera
  // space; `proved` comes in with the parent's proofs and goes out with this node's.
  int classify(uint32_t i, Vec3f& c, uint8_t& proved) const {
    c = proj.to_camera(m.centres[i]);
    const float r = m.radii[i];
    if (!(proved & kInside)) {
      if (c.z + r < proj.near) return 0;
      const float d[4] = {c.x * plane_x[0] - c.z * plane_x[1], -c.x * plane_x[0] - c.z * plane_x[1],
                          c.y * plane_y[0] - c.z * plane_y[1], -c.y * plane_y[0] - c.z * plane_y[1]};
      if (d[0] > r || d[1] > r || d[2] > r || d[3] > r) return 0;
      const float margin = r * 1.001f + 1e-5f * (std::fabs(c.x) + std::fabs(c.y) + c.z);
      if (c.z - margin > proj.near && d[0] < -margin && d[1] < -margin && d[2] < -margin &&
          d[3] < -margin)
        proved |= kInside;
    }
    const int cone = m.cones[i];
    if (cull_backfaces && cone < 3 && !(proved & kFront)) {
      const Vec3f& n = qsplat::decode_normal(m.normal_codes[i]);
      const Vec3f v = proj.eye - m.centres[i];
      const float nv = dot(n, v);
      const float s = qsplat::decode_cone_sine(cone);
      const float lim = (norm(v) + r) * s;
      if (nv < -r && (nv + r) * (nv + r) > lim * lim) return 1;
      // The mirror of the test above: every normal of the cone faces every point of the sphere.
      const float front = nv - r * 1.001f - 1e-5f * norm(v);
      if (front > 0 && front * front > lim * lim * 1.002f) proved |= kFront;
    }
    return 2;
  }

  // Visits node i and what lies below it, passing the nodes it draws to out.draw(node, centre in
  // camera space).
  // `deferred`: nodes at depth `split` go there (in order) instead of being visited.
  template <class Sink>
  void visit(Task task, Sink& out, LodStats& st, std::vector<Task>* deferred, int depth,
             int split) const {
    struct Item {
      uint32_t node;
      int depth;
      uint8_t proved;
    };
    std::vector<Item> stack{{task.node, depth, task.proved}};
    while (!stack.empty()) {
      auto [n, d, proved] = stack.back();
      stack.pop_back();
      ++st.visited;
      Vec3f c{0, 0, 0};
      // Roots have no cone.
      const int cls = m.child_count[n] && d == 0 ? 2 : classify(n, c, proved);
      if (cls == 0) {
        ++st.culled_frustum;
        continue;
      }
      if (cls == 1) {
        ++st.culled_cone;
        continue;
      }
      const int kids = m.child_count[n];
      const bool small = c.z > proj.near && 2 * m.radii[n] * proj.focal_px / c.z <= threshold;
      if (kids == 0 || (small && d > 0)) {
        out.draw(n, c);
        continue;
      }
      if (deferred && d + 1 == split) {
        // Children become tasks, in order (the stack pops them in reverse below otherwise).
        for (int k = 0; k < kids; ++k)
          deferred->push_back({m.first_child[n] + static_cast<uint32_t>(k), proved});
        continue;
      }
      for (int k = kids; k-- > 0;)
        stack.push_back({m.first_child[n] + static_cast<uint32_t>(k), d + 1, proved});
    }
  }
};

}  // namespace

const std::array<Vec3f, 65536>& linear_palette_565() {
  static const std::array<Vec3f, 65536> p = [] {
    float linear[256];  // each 8-bit value made linear once
    for (int v = 0; v < 256; ++v) linear[v] = srgb_to_linear(static_cast<float>(v) / 255.0f);
    std::array<Vec3f, 65536> t{};
    for (uint32_t w = 0; w < 65536; ++w) {
      const std::array<uint8_t, 3> c = decode_rgb565(static_cast<uint16_t>(w));
      t[w] = {linear[c[0]], linear[c[1]], linear[c[2]]};
    }
    return t;
  }();
  return p;
}

namespace {

// Sink of select_qsplat: the drawn nodes' splats, in order.
struct DrawSink {
  const QSplatModel& m;
  const std::array<Vec3f, 65536>& palette;
  Draws out;
  void draw(uint32_t i, const Vec3f&) {
    out.positions.push_back(m.centres[i]);
    out.normals.push_back(qsplat::decode_normal(m.normal_codes[i]));
    out.radii.push_back(m.radii[i]);
    if (!m.colors.empty()) out.colors.push_back(palette[m.colors[i]]);
  }
};

// Sink of draw_qsplat_zbuffer: each drawn node straight into the buffer, keyed by its index.
struct ZBufferSink {
  const QSplatModel& m;
  const Projection& proj;
  DepthKeyBuffer& buffer;
  uint64_t selected = 0, drawn = 0;
  void draw(uint32_t i, const Vec3f& c) {
    ++selected;
    drawn += zbuffer_disc(
        buffer, proj, c,
        [&] { return camera_direction(proj, qsplat::decode_normal(m.normal_codes[i])); },
        m.radii[i], i);
  }
};

Traversal make_traversal(const QSplatModel& m, const Projection& proj, float threshold_px,
                         bool cull_backfaces) {
  Traversal t{m, proj, threshold_px, cull_backfaces, {}, {}};
  const float tx = proj.cx / proj.focal_px, ty = proj.cy / proj.focal_px;
  const float nx = std::sqrt(1 + tx * tx), ny = std::sqrt(1 + ty * ty);
  t.plane_x[0] = 1 / nx;
  t.plane_x[1] = tx / nx;
  t.plane_y[0] = 1 / ny;
  t.plane_y[1] = ty / ny;
  return t;
}

// The top of each tree sequentially into `top`, down to a few hundred subtrees at depth 5; those
// in parallel, each into a sink made by make_sink(); then merge(top, sink) for each subtree's
// sink in order. Returns the counts.
template <class Sink, class MakeSink, class Merge>
LodStats traverse(const Traversal& t, Sink& top, MakeSink make_sink, Merge merge) {
  LodStats total;
  for (uint32_t root : t.m.roots) {
    std::vector<Task> tasks;
    t.visit({root, 0}, top, total, &tasks, 0, 5);
    std::vector<Sink> parts;
    parts.reserve(tasks.size());
    for (std::size_t k = 0; k < tasks.size(); ++k) parts.push_back(make_sink());
    std::vector<LodStats> part_stats(tasks.size());
    tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t k) {
      t.visit(tasks[k], parts[k], part_stats[k], nullptr, 5, 0);
    });
    for (std::size_t k = 0; k < tasks.size(); ++k) {
      merge(top, parts[k]);
      total.visited += part_stats[k].visited;
      total.culled_frustum += part_stats[k].culled_frustum;
      total.culled_cone += part_stats[k].culled_cone;
    }
  }
  return total;
}

void append(Draws& to, Draws&& from) {
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  to.radii.insert(to.radii.end(), from.radii.begin(), from.radii.end());
  to.colors.insert(to.colors.end(), from.colors.begin(), from.colors.end());
}

}  // namespace

DrawList select_qsplat(const QSplatModel& m, const Projection& proj, float threshold_px,
                       bool cull_backfaces, LodStats* stats) {
  const Traversal t = make_traversal(m, proj, threshold_px, cull_backfaces);
  const auto& palette = linear_palette_565();
  DrawSink top{m, palette, {}};
  const LodStats total = traverse(
      t, top,
      [&] {
        return DrawSink{m, palette, {}};
      },
      [](DrawSink& to, DrawSink& part) { append(to.out, std::move(part.out)); });
  if (stats) *stats = total;
  auto all = std::make_shared<Draws>(std::move(top.out));
  DrawList d;
  d.count = all->positions.size();
  d.positions = all->positions.data();
  d.normals = all->normals.data();
  d.radii = all->radii.data();
  d.colors = all->colors.empty() ? nullptr : all->colors.data();
  d.storage = all;
  return d;
}

QSplatZBufferCounts draw_qsplat_zbuffer(const QSplatModel& m, const Projection& proj,
                                        float threshold_px, bool cull_backfaces,
                                        DepthKeyBuffer& buffer) {
  const Traversal t = make_traversal(m, proj, threshold_px, cull_backfaces);
  ZBufferSink top{m, proj, buffer};
  QSplatZBufferCounts c;
  c.lod = traverse(
      t, top,
      [&] {
        return ZBufferSink{m, proj, buffer};
      },
      [](ZBufferSink& to, const ZBufferSink& part) {
        to.selected += part.selected;
        to.drawn += part.drawn;
      });
  c.selected = top.selected;
  c.drawn = top.drawn;
  return c;
}

}  // namespace splatkit::render
