#include "splatkit/common_origin.h"

#include <algorithm>
#include <cstddef>

namespace splatkit {

std::array<double, 3> common_origin(std::span<const std::array<double, 3>> origins) {
  std::array<double, 3> best = origins[0];
  std::size_t best_count = 0;
  for (const auto& o : origins) {
    const auto count = static_cast<std::size_t>(std::count(origins.begin(), origins.end(), o));
    if (count > best_count || (count == best_count && o < best)) {
      best = o;
      best_count = count;
    }
  }
  return best;
}

}  // namespace splatkit
