#include "normals/splat_radius.h"

#include <cmath>

namespace splatkit {

float splat_radius(std::span<const float> sq_dists, std::size_t radius_k) {
  double sum = 0;
  std::size_t used = 0;
  for (std::size_t j = 1; j < sq_dists.size() && used < radius_k; ++j) {
    const float d2 = sq_dists[j];
    if (!std::isfinite(d2)) break;  // unused slots (+inf) only follow the real neighbours
    if (d2 <= 0.0f) continue;
    sum += std::sqrt(static_cast<double>(d2));
    ++used;
  }
  return used == 0 ? 0.0f : static_cast<float>(sum / static_cast<double>(used));
}

}  // namespace splatkit
