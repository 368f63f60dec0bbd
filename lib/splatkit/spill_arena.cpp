#include "splatkit/spill_arena.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "splatkit/error.h"

namespace splatkit::spill {

namespace {

constexpr std::size_t kGranule = std::size_t{1} << 16;  // blocks are multiples of 64 KiB
constexpr std::size_t kMaxCapacity = std::size_t{8} << 40;  // 8 TiB of address space at most
constexpr auto kWatchPeriod = std::chrono::milliseconds(1);
// Blocks stay anonymous while their total is within max_memory / kAnonymousShare, less what the
// process holds besides (libraries, small allocations, thread stacks: about kBaseline), so that
// small limits keep their blocks in the file (see the header).
constexpr std::size_t kAnonymousShare = 4;
constexpr std::size_t kBaseline = std::size_t{32} << 20;

// A reserved range of address space that blocks are carved from: offsets [0, top) have been
// carved; freed ranges are kept coalesced for reuse. Guarded by the arena's mutex (top is also
// read by the watcher).
struct Blocks {
  char* base = nullptr;
  std::size_t capacity = 0;
  std::map<std::size_t, std::size_t> unused;  // offset -> bytes: freed blocks, coalesced
  std::map<std::size_t, std::size_t> used;    // offset -> bytes
  std::atomic<std::size_t> top{0};

  bool holds(const void* p) const {
    const char* c = static_cast<const char*>(p);
    return base && c >= base && c < base + capacity;
  }
  // The offset of a new block of `bytes` (first fit among the freed ranges, else at the top), or
  // false when it does not fit.
  bool carve(std::size_t bytes, std::size_t& offset) {
    auto fit = std::find_if(unused.begin(), unused.end(),
                            [&](const auto& u) { return u.second >= bytes; });
    if (fit != unused.end()) {
      offset = fit->first;
      const std::size_t rest = fit->second - bytes;
      unused.erase(fit);
      if (rest > 0) unused.emplace(offset + bytes, rest);
    } else {
      const std::size_t t = top.load(std::memory_order_relaxed);
      if (bytes > capacity - t) return false;
      offset = t;
      top.store(t + bytes, std::memory_order_release);
    }
    used.emplace(offset, bytes);
    return true;
  }
  // Adds [offset, offset + bytes) to the freed ranges, merged with its neighbours.
  void give_back(std::size_t offset, std::size_t bytes) {
    std::size_t start = offset, merged = bytes;
    auto next = unused.lower_bound(offset);
    if (next != unused.begin()) {
      auto previous = std::prev(next);
      if (previous->first + previous->second == offset) {
        start = previous->first;
        merged += previous->second;
        unused.erase(previous);
      }
    }
    if (next != unused.end() && next->first == offset + bytes) {
      merged += next->second;
      unused.erase(next);
    }
    unused[start] = merged;
  }
};

struct Arena {
  int fd = -1;
  Blocks file;       // the temporary file, mapped shared
  Blocks anonymous;  // anonymous memory, for blocks within anonymous_budget
  std::size_t max_memory = 0;
  std::size_t trigger = 0;          // resident bytes that start a trim
  std::size_t min_file_pages = 0;   // file pages resident besides the libraries' worth a trim
  std::size_t anonymous_budget = 0;
  std::size_t anonymous_bytes = 0;  // anonymous blocks in use (under the mutex)
  std::string dir;
  std::string full_message;  // TempDiskFull's
  std::mutex mutex;          // guards the Blocks and anonymous_bytes
  std::atomic<std::size_t> file_bytes{0}, peak_file_bytes{0}, trims{0};

  // Runs only when start() fails half way: a started arena lives as long as the process.
  ~Arena() {
    if (file.base) ::munmap(file.base, file.capacity);
    if (anonymous.base) ::munmap(anonymous.base, anonymous.capacity);
    if (fd >= 0) ::close(fd);
  }
};

std::atomic<Arena*> g_arena{nullptr};
std::once_flag g_started;

// The resident and file-backed resident pages (/proc/self/statm's 2nd and 3rd fields).
bool read_statm(std::size_t& resident, std::size_t& shared) {
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  char text[128];
  const ssize_t got = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (got <= 0) return false;
  text[got] = 0;
  char* p = text;
  std::strtoull(p, &p, 10);  // size
  resident = std::strtoull(p, &p, 10);
  shared = std::strtoull(p, &p, 10);
  return true;
}

// sched_setattr's argument, the kernel's first layout (linux/sched/types.h's struct sched_param
// clashes with glibc's, and glibc declares struct sched_attr only from 2.41).
struct SchedAttr {
  uint32_t size, policy;
  uint64_t flags;
  int32_t nice;
  uint32_t priority;
  uint64_t runtime, deadline, period;
};
static_assert(sizeof(SchedAttr) == 48, "SCHED_ATTR_SIZE_VER0");

// Lets the calling thread run as soon as it wakes, even when the process's other threads (or
// other processes) keep every core busy: the lowest real-time priority where the process may take
// it (CAP_SYS_NICE, or a non-zero RLIMIT_RTPRIO), else the shortest time slice of the fair
// scheduler (Linux 6.12 and later: a waking thread with a shorter slice preempts the running one;
// earlier kernels ignore it), else nothing. A thread that already runs real-time (a process
// started under chrt) keeps its priority, above its workers'. The watcher sleeps in a loop and
// works for microseconds per wake (a few milliseconds when it trims): it cannot starve the
// others.
void wake_promptly() {
  int policy = SCHED_OTHER;
  sched_param fifo{};
  if (::pthread_getschedparam(::pthread_self(), &policy, &fifo) == 0 &&
      (policy == SCHED_FIFO || policy == SCHED_RR))
    return;
  fifo.sched_priority = 1;
  if (::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &fifo) == 0) return;
  SchedAttr fair{};
  fair.size = sizeof fair;
  fair.policy = SCHED_OTHER;
  fair.nice = ::getpriority(PRIO_PROCESS, 0);  // this thread's: kept
  fair.runtime = 100'000;                      // ns: the slice (the kernel's least)
  ::syscall(SYS_sched_setattr, 0, &fair, 0);
}

// Drops the file's pages from the process whenever the resident memory reaches the trigger and
// enough of it is the file's.
[[noreturn]] void watch(Arena* a) {
  wake_promptly();
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  std::size_t resident = 0, shared = 0, libraries = 0;
  if (read_statm(resident, shared)) libraries = shared;
  for (;;) {
    std::this_thread::sleep_for(kWatchPeriod);
    if (!read_statm(resident, shared)) continue;
    if (resident * page < a->trigger || shared < libraries + a->min_file_pages) continue;
    const std::size_t top = a->file.top.load(std::memory_order_acquire);
    // MADV_DONTNEED on a shared file mapping unmaps the pages; dirty ones stay dirty in the
    // page cache, so nothing is lost, and a later touch maps them again.
    ::madvise(a->file.base, top, MADV_DONTNEED);
    a->trims.fetch_add(1, std::memory_order_relaxed);
  }
}

int open_temporary_file(const std::string& dir) {
  int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
  std::string name = dir + "/splatkit-spill-XXXXXX";
  fd = ::mkstemp(name.data());
  if (fd >= 0) ::unlink(name.c_str());
  return fd;
}

std::size_t round_up(std::size_t n, std::size_t to) { return (n + to - 1) / to * to; }

}  // namespace

const char* TempDiskFull::what() const noexcept {
  const Arena* a = g_arena.load(std::memory_order_acquire);
  return a ? a->full_message.c_str() : "the temporary directory is full";
}

std::string temporary_directory(const std::string& tmp_dir) {
  if (!tmp_dir.empty()) return tmp_dir;
  const char* env = std::getenv("TMPDIR");
  return env && *env ? env : "/tmp";
}

std::size_t free_disk_bytes(const std::string& dir) {
  struct statvfs s {};
  if (::statvfs(dir.c_str(), &s) != 0) return 0;
  return static_cast<std::size_t>(s.f_bavail) * s.f_frsize;
}

std::size_t resident_bytes() {
  std::size_t resident = 0, shared = 0;
  if (!read_statm(resident, shared)) return 0;
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

void start(std::size_t max_memory, const std::string& tmp_dir) {
  bool first = false;
  std::call_once(g_started, [&] { first = true; });
  if (!first) throw std::logic_error("spill::start called twice");
  auto owner = std::make_unique<Arena>();  // released below: blocks may be freed at exit
  Arena* a = owner.get();
  a->dir = temporary_directory(tmp_dir);
  a->full_message = "no room left in the temporary directory " + a->dir +
                    " (free disk space there, or give --tmp-dir elsewhere)";
  a->fd = open_temporary_file(a->dir);
  if (a->fd < 0)
    throw Error(ErrorKind::kUsage, "cannot create a temporary file in " + a->dir + " (" +
                                       std::strerror(errno) + "): give --tmp-dir DIR");
  a->file.capacity = std::min(kMaxCapacity, free_disk_bytes(a->dir) / kGranule * kGranule);
  if (a->file.capacity < kGranule ||
      ::ftruncate(a->fd, static_cast<off_t>(a->file.capacity)) != 0)
    throw Error(ErrorKind::kUsage, "the temporary directory " + a->dir +
                                       " has no room for a temporary file: give --tmp-dir DIR");
  void* base = ::mmap(nullptr, a->file.capacity, PROT_READ | PROT_WRITE,
                      MAP_SHARED | MAP_NORESERVE, a->fd, 0);
  if (base == MAP_FAILED)
    throw Error(ErrorKind::kUsage,
                "cannot map a temporary file in " + a->dir + ": " + std::strerror(errno));
  a->file.base = static_cast<char*>(base);
  // File systems with large folios (ext4 since Linux 6.16) cache the file in blocks of up to
  // 2 MiB and map a whole block at a fault: with a few thousand streams written at a time (a
  // scatter into buckets) that alone would be gigabytes resident, and the pages come back faster
  // than a trim drops them. MADV_NOHUGEPAGE stops the 2 MiB mappings; MADV_RANDOM stops the
  // read-ahead that allocates the large blocks (measured on a 40M-point cloud under a 400M
  // limit: the peak went from 801 to 389 MB, and a scatter from 18.5 to 3 s).
  ::madvise(a->file.base, a->file.capacity, MADV_NOHUGEPAGE);
  ::madvise(a->file.base, a->file.capacity, MADV_RANDOM);
  a->anonymous_budget =
      max_memory / kAnonymousShare > kBaseline ? max_memory / kAnonymousShare - kBaseline : 0;
  // Address space only (MAP_NORESERVE): twice the budget leaves room for fragmentation.
  if (a->anonymous_budget > 0) {
    base = ::mmap(nullptr, 2 * a->anonymous_budget, PROT_READ | PROT_WRITE,
                  MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (base != MAP_FAILED) {
      a->anonymous.base = static_cast<char*>(base);
      a->anonymous.capacity = 2 * a->anonymous_budget;
    }
  }
  a->max_memory = max_memory;
  a->trigger = static_cast<std::size_t>(static_cast<double>(max_memory) * kTrimFraction);
  a->min_file_pages =
      std::max<std::size_t>(1, max_memory / 16 / static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)));
  g_arena.store(owner.release(), std::memory_order_release);
  std::thread(watch, a).detach();
}

bool active() { return g_arena.load(std::memory_order_acquire) != nullptr; }

void* allocate(std::size_t size) {
  Arena* a = g_arena.load(std::memory_order_acquire);
  if (!a || size < kMinBlock) return nullptr;
  const std::size_t bytes = round_up(size, kGranule);
  std::size_t offset = 0;
  {
    std::lock_guard lock(a->mutex);
    if (a->anonymous_bytes + bytes <= a->anonymous_budget && a->anonymous.carve(bytes, offset)) {
      a->anonymous_bytes += bytes;
      return a->anonymous.base + offset;
    }
    if (!a->file.carve(bytes, offset)) throw TempDiskFull();
  }
  const std::size_t now = a->file_bytes.fetch_add(bytes) + bytes;
  // Reserve the disk blocks now (EOPNOTSUPP: a file system that cannot; then a full disk shows
  // as SIGBUS, as with any mapped file).
  if (::fallocate(a->fd, 0, static_cast<off_t>(offset), static_cast<off_t>(bytes)) != 0 &&
      errno != EOPNOTSUPP) {
    release(a->file.base + offset);
    throw TempDiskFull();
  }
  std::size_t peak = a->peak_file_bytes.load(std::memory_order_relaxed);
  while (now > peak && !a->peak_file_bytes.compare_exchange_weak(peak, now)) {
  }
  return a->file.base + offset;
}

namespace {

// The arena, when p lies in one of its ranges (read without the lock: the ranges never move).
Arena* arena_of(const void* p, Blocks*& blocks) {
  Arena* a = g_arena.load(std::memory_order_acquire);
  if (!a) return nullptr;
  blocks = a->file.holds(p) ? &a->file : a->anonymous.holds(p) ? &a->anonymous : nullptr;
  return blocks ? a : nullptr;
}

// Frees [offset, offset + bytes) of `blocks`: a file range's disk blocks and cached pages (which
// also leave the process), an anonymous range's pages. Under the lock.
void free_range(Arena* a, Blocks& blocks, std::size_t offset, std::size_t bytes) {
  if (&blocks == &a->file) {
    ::fallocate(a->fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, static_cast<off_t>(offset),
                static_cast<off_t>(bytes));
    a->file_bytes.fetch_sub(bytes);
  } else {
    ::madvise(blocks.base + offset, bytes, MADV_DONTNEED);
    a->anonymous_bytes -= bytes;
  }
  blocks.give_back(offset, bytes);
}

}  // namespace

bool release(void* p) noexcept {
  Blocks* blocks = nullptr;
  Arena* a = arena_of(p, blocks);
  if (!a) return false;
  std::lock_guard lock(a->mutex);
  const std::size_t offset = static_cast<std::size_t>(static_cast<char*>(p) - blocks->base);
  const auto it = blocks->used.find(offset);
  if (it == blocks->used.end()) return true;  // not a block start: never handed out
  const std::size_t bytes = it->second;
  blocks->used.erase(it);
  free_range(a, *blocks, offset, bytes);
  return true;
}

bool shrink(void* p, std::size_t size) noexcept {
  Blocks* blocks = nullptr;
  Arena* a = arena_of(p, blocks);
  if (!a) return false;
  std::lock_guard lock(a->mutex);
  const std::size_t offset = static_cast<std::size_t>(static_cast<char*>(p) - blocks->base);
  const auto it = blocks->used.find(offset);
  const std::size_t keep = round_up(std::max<std::size_t>(size, 1), kGranule);
  if (it == blocks->used.end() || keep >= it->second) return true;
  free_range(a, *blocks, offset + keep, it->second - keep);
  it->second = keep;
  return true;
}

void* allocate_block(std::size_t size) {
  if (void* p = allocate(size)) return p;
  return std::malloc(size > 0 ? size : 1);
}

void free_block(void* p) noexcept {
  if (p && !release(p)) std::free(p);
}

void check_room(std::size_t bytes) {
  const Arena* a = g_arena.load(std::memory_order_acquire);
  if (!a) return;
  const std::size_t in_use = a->file_bytes.load(), room = in_use + free_disk_bytes(a->dir);
  if (bytes <= room) return;
  auto mib = [](std::size_t b) { return std::to_string((b + (1 << 20) - 1) >> 20) + " MiB"; };
  throw Error(ErrorKind::kOutput, "the temporary directory " + a->dir + " has room for " +
                                      mib(room) + ", and this run needs about " + mib(bytes) +
                                      " there: free space, or give --tmp-dir elsewhere");
}

Stats stats() {
  Stats s;
  if (const Arena* a = g_arena.load(std::memory_order_acquire)) {
    s.max_memory = a->max_memory;
    s.file_bytes = a->file_bytes.load();
    s.peak_file_bytes = a->peak_file_bytes.load();
    s.trims = a->trims.load();
  }
  return s;
}

}  // namespace splatkit::spill
