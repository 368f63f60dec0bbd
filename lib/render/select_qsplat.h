// The QSplat traversal [Rusinkiewicz00]: which nodes of a .qs hierarchy a frame draws.
//
// From each root, depth first: a node whose sphere lies outside one of the four side planes of
// the view frustum or wholly behind the eye is culled with everything below it; with
// `cull_backfaces` (as the original viewer always does; off, a scan's open surfaces stay visible
// from both sides, as in a plain render), a node whose normal cone faces away from the eye is
// culled (back faces: with v = eye − centre, n·v < −r and (n·v + r)² > (|v| + r)²·s², s the
// cone's bound on its half-width's sine; cone code 3 never culls); otherwise a leaf, or a node
// whose projected size 2·r·focal/z is at most `threshold_px`, is drawn as a disc (centre,
// decoded normal, radius = the node's decoded radius, 5-6-5 colour made linear), and any other
// node recurses into its children. The culling is conservative for the decoded hierarchy: the
// encoder's spheres contain their subtrees and its cones bound the decoded normals below them. Deterministic: the DrawList order is the same for any thread count
// (the nodes drawn above depth 5 first, then the subtrees at depth 5, each traversed depth first
// in parallel and concatenated in order).
#pragma once

#include "formats/read_qsplat.h"
#include "render/camera.h"
#include "render/select_splats.h"
#include "render/zbuffer_splats.h"

namespace splatkit::render {

// The DrawList owns its arrays (DrawList::storage). `stats` (optional) gets the counts.
DrawList select_qsplat(const QSplatModel& model, const Projection& projection, float threshold_px,
                       bool cull_backfaces, LodStats* stats = nullptr);

struct QSplatZBufferCounts {
  LodStats lod;
  uint64_t selected = 0;  // nodes the traversal draws
  uint64_t drawn = 0;     // of those, the ones that cover a pixel (zbuffer_splat)
};

// The same traversal drawing each selected node straight into `buffer` (zbuffer_splats.h), keyed
// by its node index, with no DrawList in between: the fast path of `--blend zbuffer`.
QSplatZBufferCounts draw_qsplat_zbuffer(const QSplatModel& model, const Projection& projection,
                                        float threshold_px, bool cull_backfaces,
                                        DepthKeyBuffer& buffer);

// Linear RGB of every 5-6-5 colour word (each channel expanded to 8 bits as the format says, then
// made linear).
const std::array<Vec3f, 65536>& linear_palette_565();

}  // namespace splatkit::render
