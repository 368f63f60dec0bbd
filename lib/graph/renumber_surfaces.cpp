#include "graph/renumber_surfaces.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace splatkit::graph {

Segmentation renumber_surfaces(std::span<const uint32_t> labels, uint32_t label_count) {
  std::vector<uint32_t> id(label_count, kNoSurface);
  Segmentation seg;
  seg.surface.resize(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] >= label_count)
      throw std::invalid_argument("renumber_surfaces: label " + std::to_string(labels[i]) +
                                  " >= " + std::to_string(label_count));
    uint32_t& s = id[labels[i]];
    if (s == kNoSurface) {
      s = seg.count();
      seg.sizes.push_back(0);
    }
    seg.surface[i] = s;
    ++seg.sizes[s];
  }
  return seg;
}

}  // namespace splatkit::graph
