// surface_members: the splats of every surface, grouped — what refine_surface_borders and
// merge_small_surfaces walk surface by surface.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace splatkit::graph {

struct SurfaceMembers {
  std::vector<uint64_t> start;    // #count + 1: surface s holds members[start[s] .. start[s + 1])
  std::vector<uint32_t> members;  // #N splat indices, ascending within each surface

  std::span<const uint32_t> of(uint32_t s) const {
    return std::span(members).subspan(start[s], start[s + 1] - start[s]);
  }
};

// surface: #N ids, each < count (throws std::invalid_argument otherwise). A counting sort, O(N +
// count).
SurfaceMembers surface_members(std::span<const uint32_t> surface, uint32_t count);

}  // namespace splatkit::graph
