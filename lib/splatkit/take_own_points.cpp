#include "splatkit/take_own_points.h"

#include <numeric>

namespace splatkit {

std::vector<uint32_t> take_own_points(SplatCloud& cloud) {
  std::vector<uint32_t> keep;
  const ExtraAttribute* halo = cloud.find_extra(kHaloAttribute);
  if (halo == nullptr) {
    keep.resize(cloud.size());
    std::iota(keep.begin(), keep.end(), 0u);
    return keep;
  }
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (halo->values[i] == 0) keep.push_back(static_cast<uint32_t>(i));
  std::erase_if(cloud.extras, [](const ExtraAttribute& e) { return e.name == kHaloAttribute; });
  return keep;
}

}  // namespace splatkit
