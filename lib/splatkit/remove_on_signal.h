// Temporary files that must not outlive a run killed by Ctrl-C (SIGINT), SIGTERM or SIGHUP.
//
// While a RemoveOnSignal is alive, its path is in a process-wide registry. The first registration
// installs a handler for those three signals (a signal the process inherited as ignored, e.g.
// SIGHUP under nohup or SIGINT in a background job of a script, stays ignored). The handler
// unlinks every registered path, restores the signal's default action and re-raises it, so that
// the process dies of the signal (a shell reports 128 + N, e.g. 130 for Ctrl-C). It only calls
// unlink, signal and raise, and reads the registry without locks (async-signal-safe).
//
// The registry holds at most kMaxEntries live paths of at most kMaxPathBytes bytes each (plus the
// terminating NUL); a path beyond either limit is not registered and is left behind by a signal
// (it is still removed by its owner on normal exit and on error). Relative paths are resolved
// against the working directory at the time of the signal. Destroying (or release()-ing) a
// RemoveOnSignal unregisters the path; it never removes the file: the owner does that (or renames
// the file into place) itself.
#pragma once

#include <cstddef>
#include <string>

namespace splatkit {

class RemoveOnSignal {
 public:
  static constexpr std::size_t kMaxEntries = 64;
  static constexpr std::size_t kMaxPathBytes = 4095;

  RemoveOnSignal() = default;
  explicit RemoveOnSignal(const std::string& path);
  ~RemoveOnSignal() { release(); }
  RemoveOnSignal(const RemoveOnSignal&) = delete;
  RemoveOnSignal& operator=(const RemoveOnSignal&) = delete;

  // Unregisters the path (the file itself is left alone). Idempotent.
  void release();
  // Whether the path is in the registry (false if it was too long or the registry was full).
  bool registered() const { return slot_ >= 0; }

  // How many paths are registered now (for tests).
  static std::size_t live_count();

 private:
  int slot_ = -1;
};

}  // namespace splatkit
