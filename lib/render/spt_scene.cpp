#include "render/spt_scene.h"

#include <algorithm>

#include "splatkit/error.h"

namespace splatkit::render {

RenderScene make_spt_scene(SptModel&& m, const std::string& name) {
  if (m.leaves == 0) throw_bad_input(name, "the .spt list has no leaves");
  RenderScene s;
  // Framed by the leaves (as the plain render frames the same splats); the sphere also holds
  // every entry's centre, which select_spt.h's nearest distance needs.
  Vec3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  double sum = 0;
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m.r_min[i] == 0) {
      const Vec3f& c = m.positions[i];
      const float r = 0.5f * m.diameters[i];
      lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
      hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
      sum += r;
      s.max_radius = std::max(s.max_radius, r);
    }
  s.bounds.center = (lo + hi) * 0.5f;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const float reach = m.r_min[i] == 0 ? 0.5f * m.diameters[i] : 0.0f;
    s.bounds.radius = std::max(s.bounds.radius, norm(m.positions[i] - s.bounds.center) + reach);
  }
  s.mean_radius = static_cast<float>(sum / static_cast<double>(m.leaves));
  s.origin = m.header.origin;
  s.spt = std::make_shared<const SptModel>(std::move(m));
  return s;
}

}  // namespace splatkit::render
