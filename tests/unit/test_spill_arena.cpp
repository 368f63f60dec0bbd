// spill arena (splatkit/spill_arena.h): blocks carved from anonymous memory up to a quarter of
// the limit, then from an unlinked temporary file, freed and reused, shrunk in place, and kept intact while the watcher drops their pages to hold the
// resident memory under the limit. The arena is started once per process, so each test runs in
// a child process (a death test that must exit with 0).
#include <gtest/gtest.h>

#include <dirent.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "splatkit/error.h"
#include "splatkit/spill_arena.h"

namespace splatkit {
namespace {

// In the child: prints what failed and exits 1.
void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "failed: %s\n", what);
  std::_Exit(1);
}

// How many of the process's open files are deleted files in `dir`.
int deleted_files_in(const std::string& dir) {
  int count = 0;
  DIR* fds = ::opendir("/proc/self/fd");
  while (const dirent* e = ::readdir(fds)) {
    char target[4096];
    const std::string link = std::string("/proc/self/fd/") + e->d_name;
    const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
    if (n <= 0) continue;
    target[n] = 0;
    const std::string t = target;
    if (t.rfind(dir, 0) == 0 && t.find("(deleted)") != std::string::npos) ++count;
  }
  ::closedir(fds);
  return count;
}

// The directory's entries besides . and ..
int entries_in(const std::string& dir) {
  int count = 0;
  DIR* d = ::opendir(dir.c_str());
  while (const dirent* e = ::readdir(d))
    if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) ++count;
  ::closedir(d);
  return count;
}

std::string fresh_directory(const char* name) {
  std::string dir = testing::TempDir();
  while (!dir.empty() && dir.back() == '/') dir.pop_back();  // as the kernel names its files
  dir += std::string("/") + name + "-XXXXXX";
  if (!::mkdtemp(dir.data())) ADD_FAILURE() << "mkdtemp " << dir;
  return dir;
}

// The tests' bodies, each run in a child process that exits 0 when every check held.
[[noreturn]] void blocks_child(const std::string& dir) {
  require(!spill::active(), "active before start");
  require(spill::allocate(spill::kMinBlock) == nullptr, "a block before start");
  spill::start(std::size_t{256} << 20, dir);
  require(spill::active(), "not active after start");
  require(deleted_files_in(dir) == 1, "one open, deleted file in the directory");
  require(entries_in(dir) == 0, "the directory stays empty");
  require(spill::allocate(spill::kMinBlock - 1) == nullptr, "a block below kMinBlock");
  // Blocks up to a quarter of the limit less 32 MiB are anonymous memory, the rest the file's.
  auto* anonymous = static_cast<unsigned char*>(spill::allocate(std::size_t{32} << 20));
  require(anonymous != nullptr, "no anonymous block");
  require(spill::stats().file_bytes == 0, "a block within a quarter of the limit in the file");
  std::memset(anonymous, 0xcd, std::size_t{32} << 20);
  auto* a = static_cast<unsigned char*>(spill::allocate(std::size_t{8} << 20));
  require(a != nullptr, "no block");
  require(reinterpret_cast<std::uintptr_t>(a) % 4096 == 0, "block not page-aligned");
  std::memset(a, 0xab, std::size_t{8} << 20);
  require(spill::stats().file_bytes == std::size_t{8} << 20, "file bytes after one block");
  require(spill::shrink(a, std::size_t{5} << 20), "shrink: not the arena's");
  require(spill::stats().file_bytes == std::size_t{5} << 20, "file bytes after shrinking");
  require(a[(std::size_t{5} << 20) - 1] == 0xab, "data kept by shrinking");
  void* b = spill::allocate(std::size_t{6} << 20);  // after a's place
  require(spill::release(a), "release: not the arena's");
  void* c = spill::allocate(std::size_t{4} << 20);  // fits in a's freed place
  require(c == a, "a freed place is reused");
  int local = 0;
  require(!spill::release(&local), "a stack pointer counts as the arena's");
  require(!spill::shrink(&local, 1), "shrink of a stack pointer");
  spill::release(b);
  spill::release(c);
  require(spill::stats().file_bytes == 0, "file bytes after freeing everything");
  require(spill::stats().peak_file_bytes >= std::size_t{11} << 20, "peak file bytes");
  require(spill::shrink(anonymous, std::size_t{28} << 20), "shrink: not the anonymous block");
  require(anonymous[(std::size_t{28} << 20) - 1] == 0xcd, "anonymous data kept by shrinking");
  void* d = spill::allocate(std::size_t{4} << 20);  // the shrunk tail's room
  require(d != nullptr && spill::stats().file_bytes == 0, "a shrunk anonymous block's room");
  require(spill::release(anonymous) && spill::release(d), "release: not the anonymous blocks");
  void* e = spill::allocate(std::size_t{32} << 20);
  require(e == anonymous && spill::stats().file_bytes == 0, "the anonymous room is reused");
  spill::release(e);
  std::_Exit(0);
}

[[noreturn]] void trims_child(const std::string& dir) {
  const std::size_t before = spill::resident_bytes();
  spill::start(std::size_t{64} << 20, dir);
  constexpr std::size_t kBlocks = 8, kWords = (std::size_t{32} << 20) / 8;
  uint64_t* blocks[kBlocks];
  for (std::size_t b = 0; b < kBlocks; ++b) {  // 256 MiB in all, written
    blocks[b] = static_cast<uint64_t*>(spill::allocate(kWords * 8));
    require(blocks[b] != nullptr, "no block");
    for (std::size_t i = 0; i < kWords; ++i) blocks[b][i] = b * kWords + i;
  }
  // Touch everything again for a while, so that the watcher has to trim.
  for (int round = 0; round < 4 && spill::stats().trims == 0; ++round) {
    ::usleep(20000);
    for (std::size_t b = 0; b < kBlocks; ++b)
      for (std::size_t i = 0; i < kWords; i += 512) blocks[b][i] ^= 0;
  }
  require(spill::stats().trims > 0, "no trim with 256 MiB touched under a 64 MiB limit");
  for (std::size_t b = 0; b < kBlocks; ++b)
    for (std::size_t i = 0; i < kWords; ++i)
      require(blocks[b][i] == b * kWords + i, "a value changed");
  require(spill::resident_bytes() < before + (std::size_t{128} << 20),
          "resident memory not held down");
  std::_Exit(0);
}

[[noreturn]] void full_directory_child(const std::string& dir) {
  spill::start(std::size_t{256} << 20, dir);
  bool threw = false;
  try {
    spill::check_room(spill::free_disk_bytes(dir) + (std::size_t{1} << 30));
  } catch (const Error& e) {
    threw = e.kind() == ErrorKind::kOutput && std::string(e.what()).find(dir) != std::string::npos;
  }
  require(threw, "check_room: no kOutput error naming the directory");
  spill::check_room(std::size_t{1} << 20);  // room for that
  threw = false;
  try {
    spill::allocate(spill::free_disk_bytes(dir) + (std::size_t{1} << 30));
  } catch (const spill::TempDiskFull& e) {
    threw = std::string(e.what()).find(dir) != std::string::npos;
  }
  require(threw, "allocate beyond the disk: no TempDiskFull naming the directory");
  std::_Exit(0);
}

[[noreturn]] void unusable_directory_child() {
  bool threw = false;
  try {
    spill::start(std::size_t{256} << 20, testing::TempDir() + "/no-such-directory");
  } catch (const Error& e) {
    threw = e.kind() == ErrorKind::kUsage;
  }
  require(threw, "no usage error");
  require(!spill::active(), "active after a failed start");
  std::_Exit(0);
}

TEST(SpillArena, BlocksComeFromAnUnlinkedFileAndAreFreedShrunkAndReused) {
  const std::string dir = fresh_directory("spill-blocks");
  EXPECT_EXIT(blocks_child(dir), testing::ExitedWithCode(0), "");
  EXPECT_EQ(entries_in(dir), 0);
  ::rmdir(dir.c_str());
}

TEST(SpillArena, DataSurvivesTheWatcherDroppingPagesToHoldTheLimit) {
  const std::string dir = fresh_directory("spill-trims");
  EXPECT_EXIT(trims_child(dir), testing::ExitedWithCode(0), "");
  ::rmdir(dir.c_str());
}

TEST(SpillArena, AFullDirectoryIsReportedBeforeTheWorkAndAtTheAllocation) {
  const std::string dir = fresh_directory("spill-full");
  EXPECT_EXIT(full_directory_child(dir), testing::ExitedWithCode(0), "");
  ::rmdir(dir.c_str());
}

TEST(SpillArena, AnUnusableDirectoryIsAUsageError) {
  EXPECT_EXIT(unusable_directory_child(), testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace splatkit
