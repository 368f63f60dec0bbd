#include "splatkit/drop_halo_points.h"

#include <utility>
#include <vector>

#include "splatkit/append_points.h"
#include "splatkit/take_own_points.h"

namespace splatkit {

std::size_t drop_halo_points(SplatCloud& cloud, const std::string& name) {
  const std::vector<uint32_t> keep = take_own_points(cloud);
  const std::size_t dropped = cloud.size() - keep.size();
  if (dropped == 0) return 0;
  SplatCloud own;
  own.origin = cloud.origin;
  append_points(own, cloud, keep, name);
  cloud = std::move(own);
  return dropped;
}

}  // namespace splatkit
