// drop_small_surfaces: segment-surfaces --min-size. Surfaces with fewer than `min_size` splats
// lose their id (their splats get kNoSurface); the others keep their order (lowest splat index)
// and are numbered again 0.., so ids stay deterministic and dense. Small surfaces are not merged
// into a neighbour. min_size <= 1 keeps every surface. `segmentation` must be consistent (every
// id < count(); sizes[s] counts the splats with id s) as segment_surfaces gives it.
#pragma once

#include <cstdint>

#include "graph/segment_surfaces.h"

namespace splatkit::graph {

Segmentation drop_small_surfaces(Segmentation segmentation, uint32_t min_size);

}  // namespace splatkit::graph
