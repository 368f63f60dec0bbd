#include "render/select_splats.h"

#include "render/select_qsplat.h"
#include "render/select_spt.h"

namespace splatkit::render {

DrawList select_splats(const RenderScene& scene, const Projection& projection,
                       float lod_threshold_px, LodStats* stats, float spt_error_px,
                       bool cull_backfaces) {
  if (scene.qsplat)
    return select_qsplat(*scene.qsplat, projection, lod_threshold_px, cull_backfaces, stats);
  if (scene.spt) return select_spt(*scene.spt, scene.bounds, projection, spt_error_px, stats);
  DrawList d;
  d.count = scene.size();
  d.positions = scene.positions.data();
  d.normals = scene.normals.data();
  d.radii = scene.radii.data();
  if (!scene.axes.empty()) {
    d.axes = scene.axes.data();
    d.minor_radii = scene.minor_radii.data();
  }
  d.colors = scene.colors.empty() ? nullptr : scene.colors.data();
  d.surface_ids = scene.surface_ids.empty() ? nullptr : scene.surface_ids.data();
  if (scene.has_clip()) {
    d.clip = &scene.clip;
    d.clip_planes = scene.clip_planes.data();
  }
  return d;
}

}  // namespace splatkit::render
