#include "splatkit/output_file.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string_view>
#include <utility>

#include "splatkit/error.h"

namespace splatkit {

namespace {

std::string errno_text(int e) { return std::strerror(e); }

// The descriptor a name like /dev/stdout, /dev/fd/3 or /proc/self/fd/3 (bash's `>(...)`) stands
// for, or -1. Such a target is written through a duplicate of that descriptor, with the caller's
// offset and flags (`>> log` appends): renaming over the name would replace a link in /dev or
// /proc, and reopening it would truncate what the caller opened.
int descriptor_named(const std::string& path) {
  if (path == "/dev/stdout") return STDOUT_FILENO;
  if (path == "/dev/stderr") return STDERR_FILENO;
  for (const std::string_view prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    if (!path.starts_with(prefix) || path.size() == prefix.size() ||
        path.size() > prefix.size() + 9)
      continue;
    int fd = 0;
    for (std::size_t i = prefix.size(); i < path.size(); ++i) {
      if (path[i] < '0' || path[i] > '9') return -1;
      fd = fd * 10 + (path[i] - '0');
    }
    return fd;
  }
  return -1;
}

bool is_special(mode_t mode) {
  return S_ISFIFO(mode) || S_ISCHR(mode) || S_ISBLK(mode) || S_ISSOCK(mode);
}

}  // namespace

bool is_stream_path(const std::string& path) {
  if (path == "-" || descriptor_named(path) >= 0) return true;
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && is_special(st.st_mode);
}

namespace {

// Empty if `path` may be replaced, else why not. Permission bits do not stop root, so for root a
// file nobody may write counts as write-protected too.
std::string why_not_replaceable(const std::string& path, const struct stat& st) {
  if (::faccessat(AT_FDCWD, path.c_str(), W_OK, AT_EACCESS) != 0) {
    const int e = errno;
    if (e == EACCES || e == EPERM) return "is write-protected; not replacing it";
    return "cannot write: " + errno_text(e);
  }
  if (::geteuid() == 0 && (st.st_mode & 0222) == 0)
    return "is write-protected (no write permission for anyone); not replacing it";
  return {};
}

int connect_stream_socket(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof addr.sun_path) {
    errno = ENAMETOOLONG;
    return -1;
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int e = errno;
    ::close(fd);
    errno = e;
    return -1;
  }
  return fd;
}

std::string resolve_symlinks(const std::string& path) {
  std::unique_ptr<char, decltype(&std::free)> resolved(::realpath(path.c_str(), nullptr),
                                                       &std::free);
  return resolved ? std::string(resolved.get()) : std::string();
}

}  // namespace

OutputFile::OutputFile(const std::string& path, std::size_t buffer_size) : path_(path) {
  buf_.resize(buffer_size);
  if (path == "-") {
    fd_ = STDOUT_FILENO;
    return;
  }
  if (const int fd = descriptor_named(path); fd >= 0) {
    fd_ = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
    if (fd_ < 0)
      fail("cannot write to descriptor " + std::to_string(fd) + ": " + errno_text(errno));
    owns_fd_ = true;
    return;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    struct stat link {};
    if (errno == ENOENT && ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
      fail("is a dangling symbolic link; not writing through it");
    open_temporary(path);  // a new file (or mkstemp reports why it cannot be made)
    return;
  }
  if (S_ISDIR(st.st_mode)) fail("is a directory");
  if (is_special(st.st_mode)) {
    open_direct(st.st_mode);
    return;
  }
  if (const std::string why = why_not_replaceable(path, st); !why.empty()) fail(why);
  replaces_ = true;
  mode_ = st.st_mode & 0777;
  uid_ = st.st_uid;
  gid_ = st.st_gid;
  struct stat link {};
  if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    const std::string target = resolve_symlinks(path);
    if (target.empty()) fail("cannot resolve symbolic link: " + errno_text(errno));
    open_temporary(target);
    return;
  }
  open_temporary(path);
}

void OutputFile::open_direct(mode_t type) {
  fd_ = S_ISSOCK(type) ? connect_stream_socket(path_)
                       : ::open(path_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd_ < 0) fail("cannot open for writing: " + errno_text(errno));
  owns_fd_ = true;
}

void OutputFile::open_temporary(const std::string& target) {
  target_path_ = target;
  std::string temp = target + ".tmp.XXXXXX";
  // A name within 11 bytes of the file name limit: a short hidden one beside it instead.
  const std::size_t slash = target.rfind('/');
  const std::size_t name_bytes =
      slash == std::string::npos ? target.size() : target.size() - slash - 1;
  if (name_bytes + 11 > NAME_MAX)
    temp = target.substr(0, slash == std::string::npos ? 0 : slash + 1) + ".splatkit.tmp.XXXXXX";
  fd_ = ::mkstemp(temp.data());
  if (fd_ < 0) fail("cannot create: " + errno_text(errno));
  owns_fd_ = true;
  temp_path_ = std::move(temp);
  remove_on_signal_.emplace(temp_path_);
}

OutputFile::~OutputFile() {
  if (owns_fd_ && fd_ >= 0) ::close(fd_);
  if (uncached_fd_ >= 0) ::close(uncached_fd_);
  if (!committed_ && !temp_path_.empty()) ::unlink(temp_path_.c_str());
}

void OutputFile::fail(const std::string& what) const { throw_output(path_, what); }

void OutputFile::write_all(const char* p, std::size_t n) {
  std::size_t off = 0;
  while (off < n) {
    ssize_t k = ::write(fd_, p + off, n - off);
    if (k < 0) {
      if (errno == EINTR) continue;
      fail("write failed: " + errno_text(errno));
    }
    off += static_cast<std::size_t>(k);
  }
}

void OutputFile::flush() {
  write_all(buf_.data(), used_);
  used_ = 0;
}

void OutputFile::write(const void* data, std::size_t n) {
  if (finished_) fail("write after finish");
  if (reserved_) fail("append after reserve");
  if (n == 0) return;  // data may be null for an empty span
  const char* p = static_cast<const char*>(data);
  written_ += n;
  if (used_ + n > buf_.size()) {
    flush();
    if (n >= buf_.size()) {  // bulk data goes straight out, no extra copy
      write_all(p, n);
      return;
    }
  }
  std::memcpy(buf_.data() + used_, p, n);
  used_ += n;
}

void OutputFile::write_at(uint64_t offset, const void* data, std::size_t n) {
  if (finished_) fail("write after finish");
  if (is_direct()) fail("cannot rewrite bytes already sent");
  if (offset > written_ || n > written_ - offset) fail("rewrite past the bytes written");
  flush();
  const char* p = static_cast<const char*>(data);
  std::size_t off = 0;
  while (off < n) {
    const ssize_t k = ::pwrite(fd_, p + off, n - off, static_cast<off_t>(offset + off));
    if (k < 0) {
      if (errno == EINTR) continue;
      fail("write failed: " + errno_text(errno));
    }
    off += static_cast<std::size_t>(k);
  }
}

bool OutputFile::reserve(uint64_t size) {
  if (finished_) fail("reserve after finish");
  if (is_direct()) fail("cannot reserve space on a stream");
  flush();
  if (size < written_) fail("reserve below the bytes written");
#if defined(__linux__)
  // fallocate, not posix_fallocate: where the file system cannot reserve, glibc's fallback
  // writes zeros over the whole range.
  if (size > written_ && ::fallocate(fd_, 0, 0, static_cast<off_t>(size)) != 0) {
    const int e = errno;
    if (e == EOPNOTSUPP || e == ENOSYS) return false;
    fail("cannot reserve " + std::to_string(size) + " bytes: " + errno_text(e));
  }
  written_ = size;
  reserved_ = true;
  return true;
#else
  return false;
#endif
}

void OutputFile::write_through(uint64_t offset, const void* data, std::size_t n) {
  if (!reserved_ || finished_) fail("write through without reserve");
  if (offset > written_ || n > written_ - offset) fail("write past the reserved bytes");
  const auto* p = static_cast<const char*>(data);
  std::size_t direct = 0;  // bytes written around the cache
#if defined(__linux__) && defined(O_DIRECT)
  if (!uncached_tried_) {
    uncached_tried_ = true;
    // The same file, reopened through /proc (not by name: the name could be replaced meanwhile).
    const std::string self = "/proc/self/fd/" + std::to_string(fd_);
    uncached_fd_ = ::open(self.c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);
  }
  if (uncached_fd_ >= 0 && offset % kBlock == 0 && reinterpret_cast<uintptr_t>(p) % kBlock == 0) {
    flush();
    const std::size_t blocks = n / kBlock * kBlock;
    while (direct < blocks) {
      const ssize_t k =
          ::pwrite(uncached_fd_, p + direct, blocks - direct, static_cast<off_t>(offset + direct));
      if (k < 0 && errno == EINTR) continue;
      if (k < 0) {  // refused (some file systems refuse only at the write): the cache from here
        ::close(std::exchange(uncached_fd_, -1));  // on, where a real error shows again
        break;
      }
      direct += static_cast<std::size_t>(k) / kBlock * kBlock;  // a short write ends on a block
      if (k == 0 || static_cast<std::size_t>(k) % kBlock != 0) break;
    }
  }
#endif
  if (direct < n) write_at(offset + direct, p + direct, n - direct);
}

void OutputFile::finish() {
  if (finished_) return;
  flush();
  if (!owns_fd_) {  // stdout
    finished_ = true;
    return;
  }
  if (!temp_path_.empty()) {
    if (replaces_) {
      // Best effort: only root may give a file away; a file of one's own keeps its group if the
      // caller is in that group. Otherwise the replacement belongs to the caller.
      [[maybe_unused]] const int kept_owner = ::fchown(fd_, uid_, gid_);
      ::fchmod(fd_, mode_);
    } else {
      const mode_t mask = ::umask(0);
      ::umask(mask);
      ::fchmod(fd_, 0666 & ~mask);
    }
  }
  const int closed = ::close(fd_);
  fd_ = -1;
  if (closed != 0) fail("close failed: " + errno_text(errno));
  if (uncached_fd_ >= 0 && ::close(std::exchange(uncached_fd_, -1)) != 0)
    fail("close failed: " + errno_text(errno));
  finished_ = true;
}

void OutputFile::commit() {
  if (committed_) return;
  finish();
  if (!temp_path_.empty() && std::rename(temp_path_.c_str(), target_path_.c_str()) != 0)
    fail("cannot rename temporary file into place: " + errno_text(errno));
  committed_ = true;
  remove_on_signal_.reset();
}

}  // namespace splatkit
