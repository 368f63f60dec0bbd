#include "splatkit/remove_on_signal.h"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace splatkit {

namespace {

// A slot is free, being filled by its owner, holding a live path, or claimed by the handler (which
// then unlinks it; the process is about to die, so a claimed slot is never reused).
enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2, kClaimed = 3 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[RemoveOnSignal::kMaxPathBytes + 1] = {};
};

// Static storage: nothing is allocated after a signal arrives.
std::array<Slot, RemoveOnSignal::kMaxEntries> g_slots;
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs lock-free atomics");

constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_registered_files_and_die(int sig) {
  for (Slot& s : g_slots) {
    int live = kLive;
    if (s.state.compare_exchange_strong(live, kClaimed)) ::unlink(s.path);
  }
  // Blocked while this handler runs: delivered with the default action as soon as it returns.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_handlers() {
  for (int sig : kSignals) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_handler = remove_registered_files_and_die;
    sigemptyset(&sa.sa_mask);
    for (int other : kSignals) sigaddset(&sa.sa_mask, other);  // one cleanup at a time
    sa.sa_flags = SA_RESTART;
    ::sigaction(sig, &sa, nullptr);
  }
}

}  // namespace

RemoveOnSignal::RemoveOnSignal(const std::string& path) {
  static std::once_flag installed;
  std::call_once(installed, install_handlers);
  if (path.empty() || path.size() > kMaxPathBytes || path.find('\0') != std::string::npos) return;
  for (std::size_t i = 0; i < g_slots.size(); ++i) {
    int free = kFree;
    if (!g_slots[i].state.compare_exchange_strong(free, kFilling)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].state.store(kLive);  // publishes the bytes above to the handler
    slot_ = static_cast<int>(i);
    return;
  }
}

void RemoveOnSignal::release() {
  if (slot_ < 0) return;
  int live = kLive;
  // Fails only if the handler claimed the slot: the process is dying, leave it claimed.
  g_slots[static_cast<std::size_t>(slot_)].state.compare_exchange_strong(live, kFree);
  slot_ = -1;
}

std::size_t RemoveOnSignal::live_count() {
  std::size_t n = 0;
  for (const Slot& s : g_slots) n += s.state.load() == kLive;
  return n;
}

}  // namespace splatkit
