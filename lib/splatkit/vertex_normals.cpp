#include "splatkit/vertex_normals.h"

namespace splatkit {

std::vector<Vec3f> vertex_normals(const SplatCloud& cloud) {
  std::vector<Vec3f> normal(cloud.size(), Vec3f{0, 0, 0});
  for_each_triangle_by_vertex_range(
      cloud, [&](const std::array<uint32_t, 3>& t, uint32_t lo, uint32_t hi) {
        const Vec3f &p0 = cloud.positions[t[0]], &p1 = cloud.positions[t[1]],
                    &p2 = cloud.positions[t[2]];
        const Vec3f fn = cross(p1 - p0, p2 - p0);  // length: twice the area
        for (uint32_t v : t)
          if (v >= lo && v < hi) normal[v] += fn;
      });
  return normal;
}

}  // namespace splatkit
