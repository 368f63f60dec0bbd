#include "splatkit/vertex_normals.h"

#include <cstdint>

namespace splatkit {

std::vector<Vec3f> vertex_normals(const SplatCloud& cloud) {
  std::vector<Vec3f> normal(cloud.size(), Vec3f{0, 0, 0});
  for (std::size_t f = 0; f < cloud.face_count(); ++f) {
    const uint32_t b = cloud.face_offsets[f], e = cloud.face_offsets[f + 1];
    for (uint32_t k = b + 1; k + 1 < e; ++k) {
      const uint32_t t[3] = {cloud.face_indices[b], cloud.face_indices[k],
                             cloud.face_indices[k + 1]};
      const Vec3f &p0 = cloud.positions[t[0]], &p1 = cloud.positions[t[1]],
                  &p2 = cloud.positions[t[2]];
      const Vec3f fn = cross(p1 - p0, p2 - p0);  // length: twice the area
      for (uint32_t v : t) normal[v] += fn;
    }
  }
  return normal;
}

}  // namespace splatkit
