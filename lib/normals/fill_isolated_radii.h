// fill_isolated_radii: a radius for the splats whose kNN row found no neighbour at a finite,
// positive distance (a lone point, a far outlier whose distances overflow float), which
// splat_radius leaves at 0 and no renderer can draw.
//
// radii: #N splat radii, 0 marking the isolated ones. Each 0 becomes the median of the positive
// radii (the lower median for an even count), so an isolated point is drawn at the cloud's typical
// size: never radius 0, never a blob. Returns the number of radii filled. Throws Error(kBadInput)
// when no radius is positive and N > 0 (a single distinct point: no splat size can be estimated);
// the caller adds the file name.
#pragma once

#include <cstddef>
#include <span>

namespace splatkit {

std::size_t fill_isolated_radii(std::span<float> radii);

}  // namespace splatkit
