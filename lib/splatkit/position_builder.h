// Appends a reader's positions to a SplatCloud as float32 relative to an origin chosen from the
// file's first points (choose_origin_from_sample in splat_cloud.h).
//
// The first kOriginSampleSize points are held in float64 until the sample is complete (or
// finish() is called), then the origin is chosen and every later point is converted as it
// arrives: memory stays that of the float32 positions plus the sample. Readers check that each
// coordinate is finite and within float32 range (fits_float) before add(), where they can still
// name the line; add() and finish() throw Error(kBadInput) naming `path` and the point when a
// coordinate minus the origin is still beyond float range.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

// True for a finite value whose magnitude float32 can hold (|v| <= FLT_MAX).
bool fits_float(double v);

class PositionBuilder {
 public:
  // `choose` false: the origin stays (0, 0, 0) (sources whose coordinates are float32 already).
  PositionBuilder(SplatCloud& cloud, std::string path, bool choose = true);

  // p: file coordinates, finite.
  void add(const std::array<double, 3>& p);
  // Chooses the origin if the sample is not complete yet and appends the points held back.
  // Call it once after the last add(), before anything reads cloud.positions.
  void finish();
  // Points added so far.
  std::size_t size() const { return cloud_.positions.size() + sample_.size(); }

 private:
  void settle();
  void append(const std::array<double, 3>& p);

  SplatCloud& cloud_;
  std::string path_;
  std::vector<std::array<double, 3>> sample_;
  bool settled_ = false;
};

}  // namespace splatkit
