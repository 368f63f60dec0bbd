// SpillArena: a memory limit for a whole process (estimate-normals and build-spt --max-memory).
//
// Once started, every allocation of kMinBlock bytes or more that goes through operator new (the
// per-point arrays: positions, normals, radii, orders, kNN rows, trees) is carved from one
// temporary file mapped into memory (MAP_SHARED) instead of anonymous memory, and a watcher thread
// keeps the process's resident memory under the limit: when it reaches kTrimFraction of it, the
// file's pages are dropped from the process (madvise MADV_DONTNEED). Their contents stay in the
// file, through the kernel's page cache, which writes them to disk and evicts them under memory
// pressure, and come back on the next touch. So the process holds what it is working on: with
// work that visits memory region by region (the cloud processed piece by piece in Morton order,
// splat_pieces.h, and the sequential passes), that is far less than the whole. Allocations below
// kMinBlock (headers, per-cell lists, small buffers) stay anonymous, and so do large blocks while
// those in use total at most a quarter of the limit less 32 MiB (what the process holds besides:
// libraries, small allocations, thread stacks): the work buffers of a piece, short-lived,
// which in the file would be written to disk for nothing (the kernel writes a file's dirty pages
// back once they pass a share of the machine's memory, however soon they are freed).
// The watcher looks every millisecond and asks the scheduler to run it as soon as it wakes
// (spill_arena.cpp, wake_promptly), so that busy cores do not delay it while a pass maps fresh
// pages.
//
// The file is created unlinked (O_TMPFILE, or mkstemp and unlink at once) in the temporary
// directory, so it disappears when the process ends, however it ends (Ctrl-C, kill, crash), and
// it never clashes with another run. A block's disk space is reserved when it is carved
// (fallocate) and released when it is freed (punched out of the file), so a full disk is a clean
// TempDiskFull (a std::bad_alloc) at the allocation, never a SIGBUS on a later write.
//
// The operator new replacement that calls allocate() and release() is spill_new.cpp, linked into
// the executables (not into sanitizer builds, whose runtime owns operator new).
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <string>

namespace splatkit::spill {

inline constexpr std::size_t kMinBlock = std::size_t{4} << 20;  // 4 MiB
inline constexpr double kTrimFraction = 0.85;

// The temporary directory could not hold a new block (or the reserved address range is full).
class TempDiskFull : public std::bad_alloc {
 public:
  const char* what() const noexcept override;
};

// Starts the arena with the limit (bytes > 0) and its file in tmp_dir (empty: $TMPDIR, else
// /tmp). Once per process; a second call throws std::logic_error. Throws Error(kUsage) when
// tmp_dir is not a writable directory.
void start(std::size_t max_memory, const std::string& tmp_dir);
bool active();

// A block of `size` bytes, page-aligned, from the arena; nullptr when the arena is not started
// or size < kMinBlock (the caller then allocates as usual). Throws TempDiskFull.
void* allocate(std::size_t size);
// True when p is the arena's (its block is then freed); false for any other pointer.
bool release(void* p) noexcept;
// Shortens the arena's block at p to `size` bytes in place (its tail is freed); false, doing
// nothing, when p is not the arena's.
bool shrink(void* p, std::size_t size) noexcept;
// Blocks for code that allocates with malloc to resize or to leave pages untouched (SlotArray,
// a shrinking array): from the arena when it takes `size`, else malloc; nullptr when malloc
// fails. Freed with free_block.
void* allocate_block(std::size_t size);
void free_block(void* p) noexcept;

// When the arena runs: throws Error(kOutput) naming the temporary directory when the file cannot
// grow to `bytes` in all (its blocks in use now included). A run checks this before its work.
void check_room(std::size_t bytes);

struct Stats {
  std::size_t max_memory = 0;
  std::size_t file_bytes = 0;       // the file's blocks in use now
  std::size_t peak_file_bytes = 0;  // and at most, over the run
  std::size_t trims = 0;            // times the file's pages were dropped from the process
};
Stats stats();

// The bytes a new file in `dir` can grow to (statvfs: blocks available to an unprivileged user).
std::size_t free_disk_bytes(const std::string& dir);
// The directory start() uses for `tmp_dir`.
std::string temporary_directory(const std::string& tmp_dir);
// The process's resident memory now (/proc/self/statm), in bytes.
std::size_t resident_bytes();

}  // namespace splatkit::spill
