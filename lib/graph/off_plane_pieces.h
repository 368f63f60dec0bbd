// The pieces off a planar surface's plane: per surface of at least 2 × min_size splats its robust
// plane (fit_robust_plane.h, normals within max_normal_degrees), then the splats of a planar
// surface that lie beyond offset_scales of its scales from its plane with a normal over
// max_splat_degrees from it (or not finite), joined through the graph within their surface into
// connected pieces; the pieces of at least min_size splats (min_size at least 3), each ascending,
// in the order of their lowest splat. split_planar_surfaces and split_small_faces judge them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "graph/fit_robust_plane.h"
#include "graph/segment_surfaces.h"
#include "graph/surface_members.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct OffPlanePieces {
  SurfaceMembers groups;            // the splats of each surface
  std::vector<RobustPlane> planes;  // per surface (default where too small to fit)
  std::vector<std::vector<uint32_t>> pieces;
};

OffPlanePieces off_plane_pieces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                std::span<const Vec3f> normals, std::span<const float> radii,
                                const Segmentation& seg, double offset_scales,
                                double max_normal_degrees, double max_splat_degrees,
                                uint32_t min_size);

}  // namespace splatkit::graph
