#include "render/spt_scene.h"

#include <algorithm>

#include "render/splat_bounds.h"
#include "splatkit/error.h"

namespace splatkit::render {

RenderScene make_spt_scene(SptModel&& m, const std::string& name) {
  if (m.leaves == 0) throw_bad_input(name, "the .spt list has no leaves");
  RenderScene s;
  // Framed by the leaves by the plain render's rule (a view shows the model where it shows the
  // cloud it was built from); it must also hold every entry's centre, which select_spt.h's
  // nearest distance needs (interior centres are means of their leaves' centres, so it grows
  // only by the position codes' rounding).
  s.bounds = splat_bounds(m.size(), [&](std::size_t i, Vec3f& c, float& r) {
    c = m.positions[i];
    r = 0.5f * m.diameters[i];
    return m.r_min[i] == 0;
  });
  double sum = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const float r = 0.5f * m.diameters[i];
    if (m.r_min[i] == 0) {
      sum += r;
      s.max_radius = std::max(s.max_radius, r);
    }
    s.bounds.radius = std::max(s.bounds.radius, norm(m.positions[i] - s.bounds.center));
  }
  s.mean_radius = static_cast<float>(sum / static_cast<double>(m.leaves));
  s.origin = m.header.origin;
  s.spt = std::make_shared<const SptModel>(std::move(m));
  return s;
}

}  // namespace splatkit::render
