// refine_surface_borders: moves the splats on the borders between surfaces to the adjacent surface
// whose fitted geometry explains them best (draft).
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct RefineBordersOptions {
  uint32_t rounds = 8;
  uint32_t min_surface_size = 50;
  float min_normal_dot = -0.5f;
  double crease_sine = 0.17;
};

struct RefineBordersInfo {
  uint32_t rounds = 0;
  uint64_t moved = 0;
  uint32_t primitives = 0;
  uint32_t local = 0;
};

Segmentation refine_surface_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                    std::span<const Vec3f> normals, Segmentation segmentation,
                                    const RefineBordersOptions& options,
                                    RefineBordersInfo* info = nullptr);

}  // namespace splatkit::graph
