// Wall-clock seconds since a steady_clock time point: the phase timings tools put in --report.
#pragma once

#include <chrono>

namespace splatkit {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace splatkit
