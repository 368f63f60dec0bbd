#include "normals/orient_normals_viewpoint.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <functional>

namespace splatkit {

std::size_t orient_normals_viewpoint(std::span<const Vec3f> positions, std::span<Vec3f> normals,
                                     const std::array<double, 3>& viewpoint) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, positions.size(), 4096), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t flipped) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          // In double: a viewpoint far from the cloud must not lose the offset to rounding.
          const Vec3f& p = positions[i];
          const Vec3f& n = normals[i];
          const double towards =
              n.x * (viewpoint[0] - p.x) + n.y * (viewpoint[1] - p.y) + n.z * (viewpoint[2] - p.z);
          if (towards < 0) {
            normals[i] = -n;
            ++flipped;
          }
        }
        return flipped;
      },
      std::plus<>());
}

}  // namespace splatkit
