// False colours per splat for looking at the splat graph (splat-view --shade surface / sharp /
// clipped). Linear RGB in [0, 1], one entry per splat, ready for RenderScene::colors; the
// renderer then lights them like any albedo.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "graph/build_splat_graph.h"
#include "graph/clip_record.h"
#include "splatkit/vec3.h"

namespace splatkit::render {

// A distinct, deterministic colour per surface id: hues spaced by the golden angle (neighbouring
// ids far apart on the colour wheel), saturation and value cycling over three levels so that ids
// 1/φ apart in hue still differ. kNoSurfaceId (0xFFFFFFFF, splats in no kept surface) is grey.
Vec3f surface_color(uint32_t id);
std::vector<Vec3f> surface_colors(std::span<const uint32_t> ids);

// As in [IvoMSc] fig. 3.4 (docs/references.md): splats with a sharp edge (class edge or
// intersection) red, the rest green.
std::vector<Vec3f> sharp_colors(std::span<const graph::SplatClass> classes);

// Splats with clip partners orange, the rest light grey. table: one row per splat.
std::vector<Vec3f> clipped_colors(const graph::ClipPartnerTable& table);

}  // namespace splatkit::render
