// split_planar_surfaces: a planar surface gives up the pieces of it that lie on another plane —
// the faces that the segmentation joined to it across a blended crease (two slopes of a roof
// that meet at a valley, whose estimated normals turn from one to the other over several
// splats). Run in segment-surfaces after merge_small_surfaces (beyond [IvoMSc] §5.4,
// docs/references.md).
//
// Each surface of at least min_size splats gets a robust plane (fit_robust_plane). When it is
// planar, its splats that are off the plane — farther than offset_scales × its scale and with
// a normal more than max_splat_degrees from the plane's (either sign; a NaN normal counts as
// off) — are grouped into connected pieces over the graph's edges between them; a piece of at
// least min_size splats becomes a surface of its own when it is planar itself and its plane
// differs (normals more than max_splat_degrees apart). A piece that is not planar (both slopes
// of a gable that stands on a roof) is halved by its normals, either side of their mean across
// their direction of largest spread, and the connected parts of each half of at least min_size
// splats are judged the same way. A surface that is not planar itself (a wall and a ledge the
// segmentation joined, in like shares) is halved the same way, and a connected part of a half
// becomes a surface when it is a face: planar within max_face_degrees (the halves of a curved
// surface pass the planarity test's 25 degrees: the CAD part's boss and hole came apart), and
// its splats lie on its plane within twice their local noise (planes through each splat's
// neighbours in the part): a narrow strip of a clean cylinder passes the normals' test, not this
// one (the clean CAD part at 50 k lost 6 % of its boss without it). What is not split off stays.
// Deterministic; renumbered in the order of each surface's lowest splat.
#pragma once

#include <cstdint>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct SplitPlanesOptions {
  double offset_scales = 3;        // off the plane beyond this many scales (0: no splitting)
  double max_normal_degrees = 25;  // median angle of a planar surface's normals from its plane
  double max_splat_degrees = 30;   // a splat's normal farther from the plane's is off it
  double max_face_degrees = 10;    // median normal angle of a face split off a surface that is
                                   // not planar (stricter: halves of a curved surface pass 25)
  uint32_t min_size = 50;          // smaller surfaces and pieces stay as they are
};

// graph: symmetric neighbour rows; positions, normals, radii: #N each; segmentation: #N ids <
// count(). Throws std::invalid_argument on a size mismatch or an id out of range. `split`, when
// given, receives the number of pieces that became surfaces. O(N + E) plus the fits.
Segmentation split_planar_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                   std::span<const Vec3f> normals, std::span<const float> radii,
                                   Segmentation segmentation, const SplitPlanesOptions& options,
                                   uint32_t* split = nullptr);

}  // namespace splatkit::graph
