// Level-of-detail selection: which splats a frame draws. For now every splat of the scene; the
// QSplat / Sequential Point Tree issues replace this stage and may produce splats that are not in
// the scene (interior nodes), which is why a DrawList can own its arrays.
#pragma once

#include <cstddef>
#include <cstdint>
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
};

DrawList select_splats(const RenderScene& scene, const Projection& projection);

}  // namespace splatkit::render
