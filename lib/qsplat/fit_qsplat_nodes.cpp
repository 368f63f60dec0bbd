#include "qsplat/fit_qsplat_nodes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "qsplat/enclose_spheres.h"

namespace splatkit::qsplat {

namespace {

double cosine(const Vec3f& a, const Vec3f& b) {
  return std::clamp(static_cast<double>(dot(a, b)), -1.0, 1.0);
}

}  // namespace

void fit_qsplat_nodes(QSplatTree& t, const QSplatLeaves& leaves, bool centroid_rule, bool measure) {
  const std::size_t m = t.first_child.size();
  const bool color = !leaves.colors.empty();
  // The parents' sums, for interior nodes only (uninitialised: the pages of the bottom level,
  // all leaves, are never touched); then the outputs, for every node. Fresh pages cost more than
  // the zeros written into them: the outputs are made side by side.
  SlotArray<Sphere> centroid;
  SlotArray<Vec3f> normal;
  SlotArray<float> cone;
  SlotArray<std::array<uint8_t, 3>> rgb;
  normal.allocate(m);
  cone.allocate(m);
  if (color) rgb.allocate(m);
  if (measure) centroid.allocate(m);
  // The node outputs are uninitialised: every entry is written below, its page faulted in
  // there, in parallel, without a zeroing pass first.
  t.spheres.allocate(m);
  t.normal_codes.allocate(m);
  t.cones.allocate(m);
  if (color) t.colors.allocate(m);
  // Bottom up, level by level: each interior node from its children, a leaf child's values
  // taken from the input there (its outputs written, nothing kept for it). The input is in any
  // order: the leaves of the nodes a few places ahead are prefetched.
  const uint8_t leaf_cone = static_cast<uint8_t>(encode_cone(0));
  for (std::size_t l = t.levels() - 1; l-- > 0;) {  // the deepest level holds only leaves
    const uint32_t lb = t.level_begin[l], le = t.level_begin[l + 1];
    tbb::parallel_for(tbb::blocked_range<uint32_t>(lb, le, 1024), [&](const auto& r) {
      constexpr uint32_t kAhead = 4;  // nodes, of up to 4 children each
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        if (i + kAhead < le)
          for (int k = 0; k < t.child_count[i + kAhead]; ++k) {
            const uint32_t ahead = t.leaf[t.first_child[i + kAhead] + static_cast<uint32_t>(k)];
            if (ahead == kNoLeaf) continue;
            __builtin_prefetch(&leaves.positions[ahead]);
            __builtin_prefetch(&leaves.normals[ahead]);
            __builtin_prefetch(&leaves.radii[ahead]);
            if (color) __builtin_prefetch(&leaves.colors[ahead]);
          }
        const int c = t.child_count[i];
        if (c == 0) continue;  // a leaf: its parent writes it
        const uint32_t f = t.first_child[i];
        Vec3f child_normal[4];
        float child_cone[4];
        std::array<uint8_t, 3> child_rgb[4];
        Sphere child_centroid[4];
        for (int k = 0; k < c; ++k) {
          const uint32_t q = f + static_cast<uint32_t>(k), j = t.leaf[q];
          if (j == kNoLeaf) {
            child_normal[k] = normal[q];
            child_cone[k] = cone[q];
            if (color) child_rgb[k] = rgb[q];
            if (measure) child_centroid[k] = centroid[q];
            continue;
          }
          t.spheres[q] = {leaves.positions[j], leaves.radii[j]};
          child_normal[k] = leaves.normals[j];
          child_cone[k] = 0;
          child_centroid[k] = t.spheres[q];
          t.normal_codes[q] = static_cast<uint16_t>(encode_normal(child_normal[k]));
          t.cones[q] = leaf_cone;
          if (color) {
            child_rgb[k] = leaves.colors[j];
            t.colors[q] = encode_rgb565(child_rgb[k]);
          }
        }
        t.spheres[i] = enclose_spheres(&t.spheres[f], c, centroid_rule);
        if (measure) centroid[i] = enclose_spheres(child_centroid, c, true);
        Vec3f sum{0, 0, 0};
        for (int k = 0; k < c; ++k) sum += child_normal[k];
        normal[i] = squared_norm(sum) > 0 ? normalized(sum) : child_normal[0];
        if (color) {
          std::array<int, 3> acc{0, 0, 0};
          for (int k = 0; k < c; ++k)
            for (int j = 0; j < 3; ++j) acc[j] += child_rgb[k][j];
          for (int j = 0; j < 3; ++j) rgb[i][j] = static_cast<uint8_t>((acc[j] + c / 2) / c);
        }
        t.normal_codes[i] = static_cast<uint16_t>(encode_normal(normal[i]));
        const Vec3f& dn = decode_normal(t.normal_codes[i]);
        // The widest child: angle to its normal plus its own cone. Among children without a cone
        // (leaves, mostly) the widest is the one of least cosine: one arc cosine for them all.
        double theta = 0, least_cos = 2;
        for (int k = 0; k < c; ++k) {
          const double cos = cosine(dn, decode_normal(t.normal_codes[f + k]));
          if (child_cone[k] == 0)
            least_cos = std::min(least_cos, cos);
          else
            theta = std::max(theta, std::acos(cos) + child_cone[k]);
        }
        if (least_cos <= 1) theta = std::max(theta, std::acos(least_cos));
        cone[i] = static_cast<float>(theta + 1e-6);  // float rounding of the sum, upwards
        t.cones[i] = static_cast<uint8_t>(encode_cone(cone[i]));
        if (color) t.colors[i] = encode_rgb565(rgb[i]);
      }
    });
  }
  if (!measure) return;
  double sum = 0, sum_centroid = 0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < m; ++i)
    if (t.child_count[i] > 0) {
      sum += t.spheres[i].radius;
      sum_centroid += centroid[i].radius;
      ++interior;
    }
  t.mean_interior_radius = interior ? sum / interior : 0;
  t.mean_interior_radius_centroid = interior ? sum_centroid / interior : 0;
}

}  // namespace splatkit::qsplat
