#include "splatkit/position_builder.h"

#include <cfloat>
#include <cmath>
#include <string>

#include "splatkit/error.h"

namespace splatkit {

bool fits_float(double v) { return std::fabs(v) <= static_cast<double>(FLT_MAX); }

PositionBuilder::PositionBuilder(SplatCloud& cloud, std::string path, bool choose)
    : cloud_(cloud), path_(std::move(path)), settled_(!choose) {
  if (!choose) cloud_.origin = {0, 0, 0};
}

void PositionBuilder::add(const std::array<double, 3>& p) {
  if (settled_) return append(p);
  sample_.push_back(p);
  if (sample_.size() == kOriginSampleSize) settle();
}

void PositionBuilder::finish() {
  if (!settled_) settle();
}

void PositionBuilder::settle() {
  cloud_.origin = choose_origin_from_sample(sample_);
  settled_ = true;
  for (const auto& p : sample_) append(p);
  sample_.clear();
  sample_.shrink_to_fit();
}

void PositionBuilder::append(const std::array<double, 3>& p) {
  const std::array<double, 3>& o = cloud_.origin;
  const Vec3f q{static_cast<float>(p[0] - o[0]), static_cast<float>(p[1] - o[1]),
                static_cast<float>(p[2] - o[2])};
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
    throw_bad_input(path_, "point " + std::to_string(cloud_.positions.size()) +
                               ": a coordinate minus the origin is beyond float range");
  cloud_.positions.push_back(q);
}

}  // namespace splatkit
