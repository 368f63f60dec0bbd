// From the stored clip record to the render-time planes (see clip_record.h).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "graph/clip_record.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// One ClipPlane per entry of table.partners (same order), from the partners' centres and unit
// normals. positions, normals: #N (table.num_splats()); throws std::invalid_argument when the
// sizes differ. The table is assumed consistent (ClipPartnerTable::check_consistent).
std::vector<ClipPlane> make_clip_planes(const ClipPartnerTable& table,
                                        std::span<const Vec3f> positions,
                                        std::span<const Vec3f> normals);

// The fragment-test view of splat i; planes must come from make_clip_planes(table, ...)
// (#table.partners).
inline ClipView clip_view(const ClipPartnerTable& table, std::span<const ClipPlane> planes,
                          std::size_t i) {
  const uint64_t begin = table.offsets[i];
  ClipView view;
  view.planes = planes.data() + begin;
  view.flags = table.flags.data() + begin;
  view.count = static_cast<uint32_t>(table.offsets[i + 1] - begin);
  view.combine_intersection = (table.splat_flags[i] & kClipCombineIntersection) != 0;
  return view;
}

}  // namespace splatkit::graph
