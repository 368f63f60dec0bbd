#include "graph/drop_small_surfaces.h"

#include <utility>
#include <vector>

namespace splatkit::graph {

Segmentation drop_small_surfaces(Segmentation seg, uint32_t min_size) {
  if (min_size <= 1) return seg;  // every surface has a splat
  std::vector<uint32_t> new_id(seg.count(), kNoSurface);
  Segmentation out;
  for (uint32_t s = 0; s < seg.count(); ++s)
    if (seg.sizes[s] >= min_size) {
      new_id[s] = out.count();
      out.sizes.push_back(seg.sizes[s]);
    }
  out.surface.reserve(seg.surface.size());
  for (uint32_t id : seg.surface) out.surface.push_back(id == kNoSurface ? kNoSurface : new_id[id]);
  return out;
}

}  // namespace splatkit::graph
