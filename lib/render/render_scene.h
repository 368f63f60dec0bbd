// The renderer's copy of a splat cloud: structure-of-arrays in the cloud's local frame, colours
// converted once to linear RGB, plus the bounds the camera layer frames. Built once per input and
// shared by every frame (turntables render many frames of one scene).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "graph/clip_record.h"
#include "render/camera.h"
#include "splatkit/splat_cloud.h"

namespace splatkit {
struct QSplatModel;  // formats/read_qsplat.h
struct SptModel;     // formats/read_spt.h
}

namespace splatkit::render {

struct RenderScene {
  std::vector<Vec3f> positions;       // #N disc centres
  std::vector<Vec3f> normals;         // #N unit normals
  std::vector<float> radii;           // #N disc radii (> 0); ellipses: the semi-axis along axes
  std::vector<Vec3f> axes;            // #N unit axes of elliptic splats, or empty (circles)
  std::vector<float> minor_radii;     // #N semi-axes along normal × axis, or empty
  std::vector<Vec3f> colors;          // #N linear RGB in [0, 1], or empty (grey albedo)
  std::vector<uint32_t> surface_ids;  // #N surface ids (segment-surfaces), or empty: one surface;
                                      // 0xFFFFFFFF (no surface) is a surface like any other
  // Clip partners (graph/clip_record.h; build-splat-graph's CLIP chunk), or an empty table: nothing
  // is clipped. clip_planes: #clip.partners, made from `positions` and `normals` of this scene, so
  // they are in the same (local) frame as the fragments. Set with attach_clip_partners.
  graph::ClipPartnerTable clip;
  std::vector<graph::ClipPlane> clip_planes;
  BoundingSphere bounds;  // encloses every disc
  // Added to the local frame above to give the file's coordinates (SplatCloud::origin); zero for
  // QSplat and SPT files, whose coordinates are the local frame.
  std::array<double, 3> origin{0, 0, 0};
  float mean_radius = 0, max_radius = 0;
  // A QSplat hierarchy (qsplat_scene.h) instead of the arrays above, which then stay empty: each
  // frame draws the nodes its traversal selects.
  std::shared_ptr<const QSplatModel> qsplat;
  // A Sequential Point Tree's list (spt_scene.h) instead, likewise: each frame draws the entries
  // select_spt.h selects.
  std::shared_ptr<const SptModel> spt;

  std::size_t size() const;  // splats, or a QSplat hierarchy's or an SPT list's leaves
  bool has_clip() const { return !clip.partners.empty(); }
};

// Converts `cloud` (taking its arrays). Throws Error(kBadInput) naming `name` when the cloud has
// no normals or no radii (the message names the tool that computes them: estimate-normals), when
// it is empty, or when a radius is not a positive finite number. Zero-length normals are
// rejected the same way. sRGB-encoded 8- or 16-bit colours become linear floats.
RenderScene make_render_scene(SplatCloud&& cloud, const std::string& name);

// Gives the scene the clip partner table (one row per splat of the scene, same order) and builds
// its render-time planes from the scene's positions and unit normals. Throws Error(kBadInput)
// naming `name` when the table's splat count differs from the scene's (a stale chunk) or the
// table is not consistent (ClipPartnerTable::check_consistent).
void attach_clip_partners(RenderScene& scene, graph::ClipPartnerTable table,
                          const std::string& name);

// Linear value of an sRGB-encoded channel in [0, 1], and back.
float srgb_to_linear(float v);
float linear_to_srgb(float v);

}  // namespace splatkit::render
