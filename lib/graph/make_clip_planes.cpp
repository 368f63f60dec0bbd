#include "graph/make_clip_planes.h"

#include <stdexcept>

namespace splatkit::graph {

std::vector<ClipPlane> make_clip_planes(const ClipPartnerTable& table,
                                        std::span<const Vec3f> positions,
                                        std::span<const Vec3f> normals) {
  if (positions.size() != table.num_splats() || normals.size() != table.num_splats())
    throw std::invalid_argument("make_clip_planes: positions/normals do not match the table");
  std::vector<ClipPlane> planes(table.partners.size());
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const uint32_t j = table.partners[k];
    planes[k] = make_clip_plane(positions[j], normals[j], table.flags[k]);
  }
  return planes;
}

}  // namespace splatkit::graph
