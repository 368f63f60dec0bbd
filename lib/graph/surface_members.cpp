#include "graph/surface_members.h"

#include <stdexcept>

namespace splatkit::graph {

SurfaceMembers surface_members(std::span<const uint32_t> surface, uint32_t count) {
  SurfaceMembers out;
  out.start.assign(std::size_t{count} + 1, 0);
  for (uint32_t s : surface) {
    if (s >= count) throw std::invalid_argument("surface_members: surface id out of range");
    ++out.start[s + 1];
  }
  for (uint32_t s = 0; s < count; ++s) out.start[s + 1] += out.start[s];
  out.members.resize(surface.size());
  std::vector<uint64_t> at(out.start.begin(), out.start.end() - 1);
  for (std::size_t i = 0; i < surface.size(); ++i) out.members[at[surface[i]]++] = uint32_t(i);
  return out;
}

}  // namespace splatkit::graph
