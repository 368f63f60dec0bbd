#include "normals/fill_isolated_radii.h"

#include <algorithm>
#include <cstddef>
#include <vector>

#include "splatkit/error.h"

namespace splatkit {

std::size_t fill_isolated_radii(std::span<float> radii) {
  std::vector<float> positive;
  std::size_t isolated = 0;
  for (const float r : radii) {
    if (r > 0.0f)
      positive.push_back(r);
    else
      ++isolated;
  }
  if (isolated == 0) return 0;
  if (positive.empty())
    throw Error(ErrorKind::kBadInput,
                "no two distinct points: a splat radius needs a neighbour at a positive distance");
  const auto mid = positive.begin() + static_cast<std::ptrdiff_t>((positive.size() - 1) / 2);
  std::nth_element(positive.begin(), mid, positive.end());
  const float median = *mid;
  for (float& r : radii)
    if (!(r > 0.0f)) r = median;
  return isolated;
}

}  // namespace splatkit
