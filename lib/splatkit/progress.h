// Progress reporting: a GDAL-style callback for library code, and the reporter the tools attach.
//
// Library functions take `const ProgressFn&` and call it with a fraction in [0, 1] and a short
// phase name; they never print. A negative fraction means the total is unknown (reading a pipe):
// the phase then says how far the work is, e.g. "read 120 MiB". A callback stops the work by
// throwing Cancelled. The tools' Progress draws a bar on stderr only when stderr is a
// terminal and -q was not given, and prints one summary line at the end (count, time, rate, peak
// RSS) unless -q.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

namespace splatkit {

using ProgressFn = std::function<void(double fraction, const char* phase)>;

// Thrown by a progress callback to stop the work in progress; library code lets it through and
// writes no output (outputs are renamed into place only when complete). It is not a
// splatkit::Error, so that code catching bad input does not take a cancel for one.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// A callback that does nothing (the default argument of library functions).
const ProgressFn& no_progress();

// Peak resident set size of this process in bytes: the high-water mark of its image since its
// exec (/proc/self/status VmHWM; getrusage where that is missing).
uint64_t peak_rss_bytes();

class Progress {
 public:
  Progress(std::string tool, bool quiet);
  ~Progress();
  // The callback to hand to library code. Throttled to ~10 redraws per second.
  ProgressFn callback();
  // Clears the bar and prints "<tool>: <count> <unit> in <t> s (<rate> <unit>/s), peak RSS <m> MiB"
  // plus `extra` when given.
  void finish(uint64_t count, const std::string& unit = "points", const std::string& extra = "");
  double elapsed_seconds() const;

 private:
  void draw(double fraction, const char* phase);
  void clear();

  std::string tool_;
  bool quiet_;
  bool tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace splatkit
