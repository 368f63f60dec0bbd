#include "splatkit/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "splatkit/error.h"

namespace splatkit {

OutputFile::OutputFile(const std::string& path, std::size_t buffer_size) : path_(path) {
  buf_.resize(buffer_size);
  if (path == "-") {
    fd_ = STDOUT_FILENO;
    return;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) fail("is a directory");
  temp_path_ = path + ".tmp.XXXXXX";
  fd_ = ::mkstemp(temp_path_.data());
  if (fd_ < 0) {
    int e = errno;
    temp_path_.clear();
    fail(std::string("cannot create: ") + std::strerror(e));
  }
}

OutputFile::~OutputFile() {
  if (!committed_ && !temp_path_.empty()) {
    if (fd_ >= 0) ::close(fd_);
    ::unlink(temp_path_.c_str());
  }
}

void OutputFile::fail(const std::string& what) const { throw_output(path_, what); }

void OutputFile::flush() {
  std::size_t off = 0;
  while (off < used_) {
    ssize_t k = ::write(fd_, buf_.data() + off, used_ - off);
    if (k < 0) {
      if (errno == EINTR) continue;
      fail(std::string("write failed: ") + std::strerror(errno));
    }
    off += static_cast<std::size_t>(k);
  }
  used_ = 0;
}

void OutputFile::write(const void* data, std::size_t n) {
  if (committed_) fail("write after commit");
  if (n == 0) return;  // data may be null for an empty span
  const char* p = static_cast<const char*>(data);
  written_ += n;
  if (used_ + n > buf_.size()) {
    flush();
    if (n >= buf_.size()) {  // bulk data goes straight out, no extra copy
      std::size_t off = 0;
      while (off < n) {
        ssize_t k = ::write(fd_, p + off, n - off);
        if (k < 0) {
          if (errno == EINTR) continue;
          fail(std::string("write failed: ") + std::strerror(errno));
        }
        off += static_cast<std::size_t>(k);
      }
      return;
    }
  }
  std::memcpy(buf_.data() + used_, p, n);
  used_ += n;
}

void OutputFile::commit() {
  if (committed_) return;
  flush();
  if (temp_path_.empty()) {  // stdout
    committed_ = true;
    return;
  }
  mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd_, 0666 & ~mask);
  if (::close(fd_) != 0) {
    fd_ = -1;
    fail(std::string("close failed: ") + std::strerror(errno));
  }
  fd_ = -1;
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0)
    fail(std::string("cannot rename temporary file into place: ") + std::strerror(errno));
  committed_ = true;
}

}  // namespace splatkit
