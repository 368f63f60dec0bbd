// OutputFile: atomic replacement of regular files (mode and owner kept, write-protected files
// refused), direct writes into FIFOs, devices, sockets and /dev/fd/N, symlinks followed as `cp`
// does, and no temporary file left by an error or a fatal signal.
#include "splatkit/output_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "splatkit/aligned_buffer.h"
#include "splatkit/error.h"
#include "splatkit/remove_on_signal.h"

namespace splatkit {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

void put(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

mode_t mode_of(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
  return st.st_mode;
}

// Every name in `dir` (sorted), to show that no temporary file is left beside a target.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

void write_and_commit(const std::string& path, const std::string& bytes) {
  OutputFile out(path);
  out.write(bytes);
  out.commit();
}

// Expects OutputFile(path) to refuse with kOutput and a message containing `what`.
void expect_refused(const std::string& path, const std::string& what) {
  try {
    OutputFile out(path);
    ADD_FAILURE() << path << " accepted; expected: " << what;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kOutput) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("output_file_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_);
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(OutputFileTest, NewFileGetsTheUmaskMode) {
  const mode_t old_mask = ::umask(027);
  write_and_commit(at("new.bin"), "abc");
  ::umask(old_mask);
  EXPECT_EQ(slurp(at("new.bin")), "abc");
  EXPECT_EQ(mode_of(at("new.bin")) & 07777, 0640u);
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"new.bin"});
}

TEST_F(OutputFileTest, WriteAtRewritesBytesAlreadyWrittenAndRefusesPastThem) {
  OutputFile out(at("patched.bin"));
  out.write(std::string("header...."));
  out.write(std::string(3 << 20, 'x'));  // past the buffer: some bytes are on disk already
  out.write(std::string("tail"));
  out.write_at(6, "HEAD", 4);
  out.write_at((3 << 20) + 10, "TA", 2);
  EXPECT_THROW(out.write_at((3 << 20) + 12, "tail!", 5), Error);
  out.write(std::string("!"));
  out.commit();
  const std::string got = slurp(at("patched.bin"));
  ASSERT_EQ(got.size(), std::size_t{(3 << 20) + 15});
  EXPECT_EQ(got.substr(0, 10), "headerHEAD");
  EXPECT_EQ(got.substr(got.size() - 5), "TAil!");
  EXPECT_EQ(std::count(got.begin(), got.end(), 'x'), 3 << 20);
}

TEST_F(OutputFileTest, ReservedFileIsWrittenThroughAndReplacesTheOldOneOnCommit) {
  write_and_commit(at("filled.bin"), "old contents");
  OutputFile out(at("filled.bin"));
  out.write(std::string("head"));
  constexpr std::size_t kSize = 5 * OutputFile::kBlock + 100;
  if (!out.reserve(kSize)) GTEST_SKIP() << "no block reservation on this file system";
  EXPECT_EQ(out.bytes_written(), kSize);
  EXPECT_THROW(out.write(std::string("x")), Error);  // no appending after reserve
  // Aligned buffers: whole blocks around the cache where the file system allows, the rest (and
  // an unaligned range) through the cache; the bytes not written read as zeros.
  const AlignedBuffer block = make_aligned_buffer(3 * OutputFile::kBlock + 100, OutputFile::kBlock);
  std::memset(block.get(), 'b', 3 * OutputFile::kBlock + 100);
  EXPECT_THROW(out.write_through(kSize - 1, block.get(), 2), Error);
  out.write_through(2 * OutputFile::kBlock, block.get(), 3 * OutputFile::kBlock + 100);
  out.write_through(OutputFile::kBlock, block.get(), OutputFile::kBlock - 1);
  out.write_through(4097 + 10, "abc", 3);  // unaligned: through write_at
  out.write_at(0, "HE", 2);
  EXPECT_EQ(slurp(at("filled.bin")), "old contents");  // the old file until commit
  out.commit();
  const std::string got = slurp(at("filled.bin"));
  ASSERT_EQ(got.size(), kSize);
  EXPECT_EQ(got.substr(0, 4), "HEad");
  EXPECT_EQ(got.substr(4, OutputFile::kBlock - 4), std::string(OutputFile::kBlock - 4, '\0'));
  EXPECT_EQ(got.substr(OutputFile::kBlock, 10), std::string(10, 'b'));
  EXPECT_EQ(got.substr(4097 + 10, 3), "abc");
  EXPECT_EQ(got.substr(4097 + 13, OutputFile::kBlock - 4097 - 13 + 4095),
            std::string(OutputFile::kBlock - 4097 - 13 + 4095, 'b'));
  EXPECT_EQ(got[2 * OutputFile::kBlock - 1], '\0');
  EXPECT_EQ(got.substr(2 * OutputFile::kBlock), std::string(3 * OutputFile::kBlock + 100, 'b'));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"filled.bin"});
}

TEST_F(OutputFileTest, ReserveIsRefusedForDirectTargets) {
  OutputFile out("/dev/null");
  EXPECT_THROW(out.reserve(10), Error);
  EXPECT_THROW(out.write_through(0, "x", 1), Error);
}

TEST_F(OutputFileTest, WriteAtIsRefusedForDirectTargets) {
  OutputFile out("/dev/null");
  out.write(std::string("abc"));
  EXPECT_THROW(out.write_at(0, "x", 1), Error);
}

TEST_F(OutputFileTest, ReplacingAFileKeepsItsMode) {
  put(at("old.bin"), "old contents");
  ASSERT_EQ(::chmod(at("old.bin").c_str(), 0604), 0);
  const mode_t old_mask = ::umask(022);
  write_and_commit(at("old.bin"), "new");
  ::umask(old_mask);
  EXPECT_EQ(slurp(at("old.bin")), "new");
  EXPECT_EQ(mode_of(at("old.bin")) & 07777, 0604u);
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"old.bin"});
}

TEST_F(OutputFileTest, RootKeepsTheOwnerOfAReplacedFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "only root can give a file to another user";
  put(at("theirs.bin"), "theirs");
  ASSERT_EQ(::chown(at("theirs.bin").c_str(), 65534, 65534), 0);
  write_and_commit(at("theirs.bin"), "replaced");
  struct stat st {};
  ASSERT_EQ(::stat(at("theirs.bin").c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 65534u);
  EXPECT_EQ(st.st_gid, 65534u);
  EXPECT_EQ(slurp(at("theirs.bin")), "replaced");
}

// Mode 0444 stops everyone, root included (whom permission bits alone would not stop).
TEST_F(OutputFileTest, WriteProtectedFileIsRefusedAndKept) {
  put(at("ro.bin"), "precious");
  ASSERT_EQ(::chmod(at("ro.bin").c_str(), 0444), 0);
  expect_refused(at("ro.bin"), "is write-protected");
  EXPECT_EQ(slurp(at("ro.bin")), "precious");
  EXPECT_EQ(mode_of(at("ro.bin")) & 07777, 0444u);
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"ro.bin"});
}

TEST_F(OutputFileTest, DirectoryIsRefused) {
  fs::create_directory(at("sub"));
  expect_refused(at("sub"), "is a directory");
  EXPECT_TRUE(fs::is_directory(at("sub")));
}

TEST_F(OutputFileTest, MissingDirectoryIsReported) {
  expect_refused(at("no/such/dir/out.bin"), "cannot create: No such file or directory");
}

// As `cp`: the link stays a link, its target gets the bytes, the temporary file goes beside the
// target (a rename across directories could cross file systems).
TEST_F(OutputFileTest, SymlinkIsFollowedToItsTarget) {
  fs::create_directory(at("real"));
  fs::create_directory(at("links"));
  put(at("real/target.bin"), "old");
  ASSERT_EQ(::chmod(at("real/target.bin").c_str(), 0600), 0);
  fs::create_symlink("../real/target.bin", at("links/link.bin"));
  {
    OutputFile out(at("links/link.bin"));
    out.write("through the link");
    EXPECT_EQ(names_in(at("links")), std::vector<std::string>{"link.bin"});
    ASSERT_EQ(names_in(at("real")).size(), 2u) << "the temporary file sits beside the target";
    out.commit();
  }
  EXPECT_TRUE(fs::is_symlink(at("links/link.bin")));
  EXPECT_EQ(fs::read_symlink(at("links/link.bin")), fs::path("../real/target.bin"));
  EXPECT_EQ(slurp(at("real/target.bin")), "through the link");
  EXPECT_EQ(mode_of(at("real/target.bin")) & 07777, 0600u);
  EXPECT_EQ(names_in(at("real")), std::vector<std::string>{"target.bin"});
}

TEST_F(OutputFileTest, DanglingSymlinkIsRefused) {
  fs::create_symlink("nowhere.bin", at("dangling.bin"));
  expect_refused(at("dangling.bin"), "dangling symbolic link");
  EXPECT_TRUE(fs::is_symlink(at("dangling.bin")));
  EXPECT_FALSE(fs::exists(at("nowhere.bin")));
}

// Waits up to 10 s for `fd` to be readable (so that a regression fails instead of hanging).
bool wait_readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, 10000) > 0;
}

TEST_F(OutputFileTest, FifoIsWrittenDirectly) {
  ASSERT_EQ(::mkfifo(at("pipe").c_str(), 0600), 0);
  const int fd = ::open(at("pipe").c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  const std::string bytes(3 << 20, 'z');  // more than the buffer and the pipe's capacity
  std::string got;
  std::thread reader([&] {
    char buf[65536];
    while (wait_readable(fd)) {
      const ssize_t k = ::read(fd, buf, sizeof buf);
      if (k > 0) got.append(buf, static_cast<std::size_t>(k));
      if (k == 0 || (k < 0 && errno != EAGAIN && errno != EINTR)) break;
    }
  });
  {
    OutputFile out(at("pipe"));
    EXPECT_TRUE(out.is_direct());
    out.write(bytes);
    out.commit();
  }
  reader.join();
  ::close(fd);
  EXPECT_EQ(got.size(), bytes.size());
  EXPECT_TRUE(got == bytes);
  EXPECT_TRUE(S_ISFIFO(mode_of(at("pipe"))));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"pipe"});
}

// A node like /dev/null (major 1, minor 3), made here so that a regression cannot hurt the real
// one.
TEST_F(OutputFileTest, CharacterDeviceStaysADevice) {
  if (::mknod(at("null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make a device node here";
  write_and_commit(at("null"), "discarded");
  EXPECT_TRUE(S_ISCHR(mode_of(at("null"))));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"null"});
}

TEST_F(OutputFileTest, UnixSocketIsWrittenDirectly) {
  const std::string path = at("sock");
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof addr.sun_path) GTEST_SKIP() << "temp path too long for a socket";
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int server = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(server, 0);
  ASSERT_EQ(::bind(server, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(::listen(server, 1), 0);
  std::string got;
  std::thread reader([&] {
    if (!wait_readable(server)) return;
    const int c = ::accept(server, nullptr, nullptr);
    char buf[4096];
    for (ssize_t k; (k = ::read(c, buf, sizeof buf)) > 0;) got.append(buf, k);
    ::close(c);
  });
  write_and_commit(path, "over the socket");
  reader.join();
  ::close(server);
  EXPECT_EQ(got, "over the socket");
  EXPECT_TRUE(S_ISSOCK(mode_of(path)));
}

// /dev/fd/N is the caller's descriptor: its offset and O_APPEND hold, nothing is truncated.
TEST_F(OutputFileTest, DevFdAppendsToTheCallersDescriptor) {
  put(at("log.txt"), "first\n");
  const int fd = ::open(at("log.txt").c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(fd, 0);
  write_and_commit("/dev/fd/" + std::to_string(fd), "second\n");
  EXPECT_EQ(::write(fd, "third\n", 6), 6) << "the caller's descriptor stays open";
  ::close(fd);
  EXPECT_EQ(slurp(at("log.txt")), "first\nsecond\nthird\n");
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"log.txt"});
  expect_refused("/dev/fd/" + std::to_string(fd), "Bad file descriptor");
}

TEST_F(OutputFileTest, ErrorLeavesNoTemporaryFileAndKeepsTheOldOne) {
  put(at("keep.bin"), "good");
  try {
    OutputFile out(at("keep.bin"));
    out.write("half");
    EXPECT_EQ(RemoveOnSignal::live_count(), 1u);
    throw Error(ErrorKind::kBadInput, "stop");
  } catch (const Error&) {
  }
  EXPECT_EQ(RemoveOnSignal::live_count(), 0u);
  EXPECT_EQ(slurp(at("keep.bin")), "good");
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"keep.bin"});
}

// A fatal signal in the middle of a write: the temporary file goes, the old output stays, and the
// process dies of that signal (what a shell reports as 128 + N).
TEST_F(OutputFileTest, FatalSignalRemovesTheTemporaryFileAndReRaises) {
  put(at("keep.bin"), "good");
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction now {};
    ASSERT_EQ(::sigaction(sig, nullptr, &now), 0);
    if (now.sa_handler == SIG_IGN)
      ::signal(sig, SIG_DFL);  // a signal ignored from the start stays so
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      OutputFile out(at("keep.bin"));
      out.write(std::string(3 << 20, 'x'));
      OutputFile other(at("other.bin"));
      other.write("y");
      ::sigaction(sig, nullptr, &now);
      if (now.sa_handler == SIG_IGN) ::_exit(77);  // the handler was set up while it was ignored
      ::raise(sig);
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 77) continue;
    EXPECT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ", status " << status;
    if (WIFSIGNALED(status)) {
      EXPECT_EQ(WTERMSIG(status), sig);
    }
    EXPECT_EQ(slurp(at("keep.bin")), "good");
    EXPECT_EQ(names_in(dir_), std::vector<std::string>{"keep.bin"}) << "signal " << sig;
  }
}

TEST(RemoveOnSignal, RegistersUpToItsCapacityAndReleases) {
  const std::size_t before = RemoveOnSignal::live_count();
  std::vector<std::unique_ptr<RemoveOnSignal>> entries;
  for (std::size_t i = 0; i < RemoveOnSignal::kMaxEntries + 3; ++i)
    entries.push_back(std::make_unique<RemoveOnSignal>("/nonexistent/" + std::to_string(i)));
  EXPECT_EQ(RemoveOnSignal::live_count(), RemoveOnSignal::kMaxEntries);
  EXPECT_FALSE(entries.back()->registered());
  RemoveOnSignal too_long(std::string(RemoveOnSignal::kMaxPathBytes + 1, 'a'));
  EXPECT_FALSE(too_long.registered());
  entries.clear();
  EXPECT_EQ(RemoveOnSignal::live_count(), before);
}

}  // namespace
}  // namespace splatkit
