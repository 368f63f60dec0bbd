// Level-of-detail selection: which splats a frame draws. Every splat of a plain scene; the nodes
// of a QSplat hierarchy that its traversal selects (select_qsplat.h), splats that are not in the
// scene (interior nodes), which is why a DrawList can own its arrays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "graph/clip_record.h"
#include "render/camera.h"
#include "render/render_scene.h"

namespace splatkit::render {

// The splats of one frame, as views into arrays that outlive the frame. Fragments refer to
// splats by their index in the DrawList, and ties between fragments are broken by that index, so
// the DrawList order is part of what makes images deterministic.
struct DrawList {
  std::size_t count = 0;
  const Vec3f* positions = nullptr;       // #count
  const Vec3f* normals = nullptr;         // #count, unit
  const float* radii = nullptr;           // #count (ellipses: the semi-axis along `axes`)
  const Vec3f* colors = nullptr;          // #count linear RGB, or null (default albedo)
  const uint32_t* surface_ids = nullptr;  // #count, or null (all one surface)
  // Clip partners by DrawList index (rows of `clip`, planes in the positions' frame), or null:
  // nothing is clipped. Splats that are not in the scene (future LOD nodes) must have none.
  const graph::ClipPartnerTable* clip = nullptr;
  const graph::ClipPlane* clip_planes = nullptr;
  // Elliptic splats: #count unit axes u (in the splat's plane) and semi-axes along normal × u, or
  // null (circles).
  const Vec3f* axes = nullptr;
  const float* minor_radii = nullptr;
  // The arrays above when they are not the scene's (a level-of-detail selection made them).
  std::shared_ptr<const void> storage = nullptr;
};

// What a level-of-detail selection did (all zero for a plain scene).
struct LodStats {
  uint64_t visited = 0;         // hierarchy nodes looked at
  uint64_t culled_frustum = 0;  // nodes (with everything below) outside the view frustum
  uint64_t culled_cone = 0;     // nodes whose normal cone faces away from the eye
  // Sequential Point Trees (select_spt.h): the prefix of the list with r_max above the model's
  // nearest distance, and the entries of that prefix whose own distance is outside [r_min, r_max).
  uint64_t spt_prefix = 0;
  uint64_t spt_culled = 0;
  // `--blend zbuffer` on an SPT scene: drawn splats written as one pixel (projected diameter at
  // most kSptPointDiameterPx, select_spt.h), and the sum of every drawn splat's projected
  // diameter in pixels (for the mean).
  uint64_t spt_points = 0;
  double spt_diameter_px_sum = 0;
  double spt_cpu_s = 0;  // CPU time of the selection and drawing, all threads
};

// Every splat of a plain scene; for a QSplat scene (RenderScene::qsplat) the nodes the QSplat
// traversal selects at `lod_threshold_px`, its normal cones culling back faces with
// `cull_backfaces` (select_qsplat.h); for an SPT scene (RenderScene::spt) the entries of the list
// whose error is within `spt_error_px` pixels (select_spt.h).
DrawList select_splats(const RenderScene& scene, const Projection& projection,
                       float lod_threshold_px = 1, LodStats* stats = nullptr,
                       float spt_error_px = 1, bool cull_backfaces = false);

}  // namespace splatkit::render
