// split_small_faces: a planar surface gives up the small faces on it that lie on a plane of their
// own — a ledge or the top of a pier a metre across, a few dozen splats, that the segmentation
// joined to the wall it stands on. Run in segment-surfaces after split_planar_surfaces, which
// leaves pieces under its min_size (beyond [IvoMSc] §5.4, docs/references.md).
//
// Each surface of at least 2 × min_size splats gets a robust plane (fit_robust_plane). When it
// is planar, its splats off the plane — farther than offset_scales × its scale and with a normal
// more than max_splat_degrees from the plane's (either sign; a NaN normal counts as off) — are
// grouped into connected pieces over the graph's edges between them. A piece of at least
// min_size splats becomes a surface of its own when it is a face and its plane is more than
// max_splat_degrees from the surface's:
//   - planar within max_face_degrees (median normal angle from its own plane);
//   - flat within its noise: its robust scale is at most twice the residual scale of planes
//     through each splat's neighbours in the piece (a strip of a curved surface bends away from
//     any one plane; on a clean part its local residuals are nil);
//   - wide: the spread of its splats along the plane's shorter in-plane axis (the root of the
//     middle eigenvalue of their covariance) is at least one splat diameter (median 2 r), so a
//     row of splats along a crease, which is off the plane with turned normals too, is not a
//     face.
// Deterministic (pieces in the order of their lowest splat); renumbered in the order of each
// surface's lowest splat (renumber_surfaces).
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct SplitSmallFacesOptions {
  double offset_scales = 3;        // off the plane beyond this many scales (0: no splitting)
  double max_normal_degrees = 25;  // median angle of a planar surface's normals from its plane
  double max_splat_degrees = 30;   // a splat's normal farther from the plane's is off it
  double max_face_degrees = 10;    // median normal angle of a face from its own plane
  uint32_t min_size = 20;          // smaller pieces stay
};

// graph: symmetric neighbour rows; positions, normals, radii: #N each; segmentation: #N ids <
// count(). Throws std::invalid_argument on a size mismatch or an id out of range. `split`, when
// given, receives the number of faces that became surfaces. O(N + E) plus the fits.
Segmentation split_small_faces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                               std::span<const Vec3f> normals, std::span<const float> radii,
                               Segmentation segmentation, const SplitSmallFacesOptions& options,
                               uint32_t* split = nullptr);

}  // namespace splatkit::graph
