#include "splatkit/progress.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace splatkit {

const ProgressFn& no_progress() {
  static const ProgressFn kNone = [](double, const char*) {};
  return kNone;
}

uint64_t peak_rss_bytes() {
  // The kernel's high-water mark of this process image (VmHWM): getrusage's ru_maxrss carries
  // over exec, so a tool started by a large process (a Python workflow engine forks itself
  // first) would report its parent's size.
  if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    unsigned long long kib = 0;
    bool found = false;
    while (!found && std::fgets(line, sizeof line, f))
      found = std::sscanf(line, "VmHWM: %llu kB", &kib) == 1;
    std::fclose(f);
    if (found) return static_cast<uint64_t>(kib) * 1024;
  }
  struct rusage ru {};
  ::getrusage(RUSAGE_SELF, &ru);
  return static_cast<uint64_t>(ru.ru_maxrss) * 1024;  // Linux reports KiB
}

Progress::Progress(std::string tool, bool quiet)
    : tool_(std::move(tool)),
      quiet_(quiet),
      tty_(!quiet && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { clear(); }

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

ProgressFn Progress::callback() {
  if (!tty_) return no_progress();
  return [this](double fraction, const char* phase) { draw(fraction, phase); };
}

void Progress::draw(double fraction, const char* phase) {
  auto now = std::chrono::steady_clock::now();
  if (drawn_ && fraction < 1.0 && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  if (fraction < 0) {  // total unknown: the phase says how far
    std::fprintf(stderr, "\r%s: %s\033[K", tool_.c_str(), phase ? phase : "");
    std::fflush(stderr);
    drawn_ = true;
    return;
  }
  if (fraction > 1) fraction = 1;
  constexpr int kWidth = 30;
  int filled = static_cast<int>(fraction * kWidth);
  std::fprintf(stderr, "\r%s: %-16.16s [%.*s%*s] %3d%%", tool_.c_str(), phase ? phase : "", filled,
               "##############################", kWidth - filled, "",
               static_cast<int>(fraction * 100));
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::clear() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

namespace {
// 1234567 -> "1.23 M"; 980 -> "980 ".
std::string si(double v) {
  char buf[32];
  if (v >= 1e9)
    std::snprintf(buf, sizeof buf, "%.3g G", v / 1e9);
  else if (v >= 1e6)
    std::snprintf(buf, sizeof buf, "%.3g M", v / 1e6);
  else if (v >= 1e3)
    std::snprintf(buf, sizeof buf, "%.3g k", v / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.3g ", v);
  return buf;
}
}  // namespace

void Progress::finish(uint64_t count, const std::string& unit, const std::string& extra) {
  clear();
  if (quiet_) return;
  double t = elapsed_seconds();
  double rate = t > 0 ? static_cast<double>(count) / t : 0.0;
  std::fprintf(stderr, "%s: %llu %s in %.3f s (%s%s/s), peak RSS %.1f MiB%s%s\n", tool_.c_str(),
               static_cast<unsigned long long>(count), unit.c_str(), t, si(rate).c_str(),
               unit.c_str(), static_cast<double>(peak_rss_bytes()) / (1024.0 * 1024.0),
               extra.empty() ? "" : ", ", extra.c_str());
}

}  // namespace splatkit
