// PlaneResidualScale: the noise of splats about planes through their neighbours, each splat left
// out of its own plane: 1.4826 × the median of their distances from those planes (a Gaussian's
// σ from the median absolute deviation). model_surfaces and split_planar_surfaces measure a
// surface's local noise with it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "graph/vec3d.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {

class PlaneResidualScale {
 public:
  // One splat: add() each neighbour's offset from it, then close() records the splat's distance
  // from its neighbours' least-squares plane (nothing with fewer than kMinNeighbours of them).
  void add(const Vec3d& d) {
    w_ += 1;
    sum_ += d;
    ss_[0] += d.x * d.x, ss_[1] += d.x * d.y, ss_[2] += d.x * d.z;
    ss_[3] += d.y * d.y, ss_[4] += d.y * d.z, ss_[5] += d.z * d.z;
  }
  void close() {
    if (w_ >= kMinNeighbours) {
      const Vec3d c = sum_ / w_;
      const std::array<double, 3> n =
          pca_normal({ss_[0] / w_ - c.x * c.x, ss_[1] / w_ - c.x * c.y, ss_[2] / w_ - c.x * c.z,
                      ss_[3] / w_ - c.y * c.y, ss_[4] / w_ - c.y * c.z, ss_[5] / w_ - c.z * c.z})
              .normal;
      residuals_.push_back(std::abs(c.x * n[0] + c.y * n[1] + c.z * n[2]));
    }
    w_ = 0;
    sum_ = {};
    ss_ = {};
  }
  // The scale over the splats closed so far; infinity when none was recorded.
  double scale() {
    if (residuals_.empty()) return std::numeric_limits<double>::infinity();
    auto mid = residuals_.begin() + static_cast<std::ptrdiff_t>(residuals_.size() / 2);
    std::nth_element(residuals_.begin(), mid, residuals_.end());
    return 1.4826 * *mid;
  }

 private:
  static constexpr double kMinNeighbours = 5;
  double w_ = 0;
  Vec3d sum_;
  std::array<double, 6> ss_{};
  std::vector<double> residuals_;
};

}  // namespace splatkit::graph
