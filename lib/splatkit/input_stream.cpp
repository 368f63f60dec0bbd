#include "splatkit/input_stream.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "splatkit/crc32c.h"
#include "splatkit/error.h"

namespace splatkit {

InputStream::InputStream(const std::string& path, std::size_t buffer_size) : path_(path) {
  if (path == "-") {
    fd_ = STDIN_FILENO;
  } else {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw_bad_input(path, std::string("cannot open: ") + std::strerror(errno));
    owns_fd_ = true;
  }
  struct stat st {};
  if (::fstat(fd_, &st) == 0) {
    if (S_ISDIR(st.st_mode)) {
      if (owns_fd_) ::close(fd_);
      throw_bad_input(path, "is a directory");
    }
    if (S_ISREG(st.st_mode)) size_ = static_cast<uint64_t>(st.st_size);
  }
#ifdef POSIX_FADV_SEQUENTIAL
  if (size_) ::posix_fadvise(fd_, 0, 0, POSIX_FADV_SEQUENTIAL);
#endif
  buf_.resize(std::max<std::size_t>(buffer_size, 4096));
}

InputStream::InputStream(std::string name, const void* data, std::size_t size)
    : path_(std::move(name)), size_(size), mem_(static_cast<const char*>(data)), end_(size) {
  eof_ = true;  // nothing more to fill: the whole input is in memory
}

InputStream::~InputStream() {
  if (owns_fd_) ::close(fd_);
}

std::string InputStream::name() const { return display_name(path_); }

void InputStream::fail(const std::string& what) const {
  throw_bad_input(path_, "byte " + std::to_string(consumed_) + ": " + what);
}

std::optional<uint64_t> InputStream::remaining() const {
  if (!size_) return std::nullopt;
  return *size_ > consumed_ ? *size_ - consumed_ : 0;
}

void InputStream::consume(const char* p, std::size_t n) {
  crc_ = crc32c(crc_, p, n);
  consumed_ += n;
  if (progress_ && consumed_ >= next_report_) report_progress();
}

void InputStream::set_progress(ProgressFn fn, std::string phase) {
  progress_ = std::move(fn);
  phase_ = std::move(phase);
  constexpr uint64_t kMiB = uint64_t{1} << 20;
  progress_step_ = size_ ? std::max<uint64_t>(kMiB, *size_ / 1000) : kMiB;
  next_report_ = consumed_ + progress_step_;
}

void InputStream::report_progress() {
  next_report_ = consumed_ + progress_step_;
  if (size_ && *size_ > 0) {
    progress_(std::min(1.0, static_cast<double>(consumed_) / static_cast<double>(*size_)),
              phase_.c_str());
    return;
  }
  progress_text_ = "read " + std::to_string(consumed_ >> 20) + " MiB";
  progress_(-1.0, progress_text_.c_str());
}

bool InputStream::fill(std::size_t want) {
  if (end_ - begin_ >= want) return true;
  if (mem_ || eof_) return false;
  if (want > buf_.size()) buf_.resize(want);
  if (begin_ > 0) {
    std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  while (end_ - begin_ < want && !eof_) {
    ssize_t got = ::read(fd_, buf_.data() + end_, buf_.size() - end_);
    if (got < 0) {
      if (errno == EINTR) continue;
      fail(std::string("read error: ") + std::strerror(errno));
    }
    if (got == 0) eof_ = true;
    end_ += static_cast<std::size_t>(got);
  }
  return end_ - begin_ >= want;
}

std::string_view InputStream::peek(std::size_t n) {
  fill(n);
  const char* base = mem_ ? mem_ : buf_.data();
  return {base + begin_, std::min(n, end_ - begin_)};
}

std::string_view InputStream::take(std::size_t n, const char* what) {
  if (!fill(n)) fail(std::string("unexpected end of file while reading ") + what);
  const char* base = mem_ ? mem_ : buf_.data();
  std::string_view v(base + begin_, n);
  begin_ += n;
  consume(v.data(), n);
  return v;
}

std::size_t InputStream::read_in_parallel(char* out, std::size_t n) {
  const off_t at = ::lseek(fd_, 0, SEEK_CUR);
  if (at < 0) fail(std::string("cannot find the read position: ") + std::strerror(errno));
  // Each piece reads until it is full or the file ends; the bytes read are those before the
  // first piece that came up short.
  constexpr std::size_t kPiece = std::size_t{1} << 22;
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  std::vector<std::size_t> got(pieces, 0);
  std::vector<int> error(pieces, 0);
  tbb::parallel_for(std::size_t{0}, pieces, [&](std::size_t i) {
    const std::size_t b = i * kPiece, len = std::min(n - b, kPiece);
    while (got[i] < len) {
      const ssize_t k =
          ::pread(fd_, out + b + got[i], len - got[i], at + static_cast<off_t>(b + got[i]));
      if (k < 0 && errno == EINTR) continue;
      if (k < 0) error[i] = errno;
      if (k <= 0) break;
      got[i] += static_cast<std::size_t>(k);
    }
  });
  std::size_t total = 0;
  for (std::size_t i = 0; i < pieces; ++i) {
    if (error[i] != 0) fail(std::string("read error: ") + std::strerror(error[i]));
    total += got[i];
    if (got[i] < std::min(n - i * kPiece, kPiece)) break;
  }
  if (::lseek(fd_, at + static_cast<off_t>(total), SEEK_SET) < 0)
    fail(std::string("cannot set the read position: ") + std::strerror(errno));
  return total;
}

std::size_t InputStream::read_some(void* dst, std::size_t n) {
  char* out = static_cast<char*>(dst);
  std::size_t done = 0;
  while (done < n) {
    if (begin_ == end_) {
      if (mem_ || eof_) break;
      // Large reads bypass the buffer: no second copy of bulk data.
      if (n - done >= buf_.size()) {
        if (size_ && n - done >= kParallelRead) {  // a regular file: pieces read side by side
          const std::size_t got = read_in_parallel(out + done, n - done);
          consume(out + done, got);
          done += got;
          if (done < n) eof_ = true;
          continue;
        }
        ssize_t got = ::read(fd_, out + done, n - done);
        if (got < 0) {
          if (errno == EINTR) continue;
          fail(std::string("read error: ") + std::strerror(errno));
        }
        if (got == 0) {
          eof_ = true;
          break;
        }
        consume(out + done, static_cast<std::size_t>(got));
        done += static_cast<std::size_t>(got);
        continue;
      }
      begin_ = end_ = 0;
      if (!fill(1)) break;
    }
    const char* base = mem_ ? mem_ : buf_.data();
    std::size_t k = std::min(n - done, end_ - begin_);
    std::memcpy(out + done, base + begin_, k);
    consume(base + begin_, k);
    begin_ += k;
    done += k;
  }
  return done;
}

void InputStream::read(void* dst, std::size_t n, const char* what) {
  if (read_some(dst, n) != n) fail(std::string("unexpected end of file while reading ") + what);
}

void InputStream::skip(uint64_t n, const char* what) {
  while (n > 0) {
    if (begin_ == end_ && !fill(1))
      fail(std::string("unexpected end of file while skipping ") + what);
    std::size_t k = static_cast<std::size_t>(std::min<uint64_t>(n, end_ - begin_));
    consume((mem_ ? mem_ : buf_.data()) + begin_, k);
    begin_ += k;
    n -= k;
  }
}

bool InputStream::read_line(std::string& line, std::size_t max_len) {
  line.clear();
  for (;;) {
    if (begin_ == end_ && !fill(1)) return !line.empty();
    const char* base = mem_ ? mem_ : buf_.data();
    const char* start = base + begin_;
    const char* nl = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
    std::size_t k = nl ? static_cast<std::size_t>(nl - start) : end_ - begin_;
    if (line.size() + k > max_len) fail("line longer than " + std::to_string(max_len) + " bytes");
    line.append(start, k);
    consume(start, k + (nl ? 1 : 0));
    begin_ += k + (nl ? 1 : 0);
    if (nl) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      return true;
    }
  }
}

bool InputStream::at_eof() { return !fill(1); }

}  // namespace splatkit
