// Buffered, forward-only reader over a file or standard input ("-").
//
// Readers stream through it instead of slurping the file: the buffer is fixed (1 MiB by
// default) whatever the file size. peek() lets format detection look at the first bytes even on a
// pipe. Every failure (truncation, I/O error) throws splatkit::Error naming the file and the byte
// offset. size_hint() is the file size when known (regular files), used by decoders to cap
// allocations: a header claiming more data than the file holds is rejected before allocating.
// set_progress() reports the bytes consumed to a ProgressFn while any reader runs on the stream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "splatkit/progress.h"

namespace splatkit {

class InputStream {
 public:
  // Opens `path` ("-" = stdin). Throws Error(kBadInput) when it cannot be opened.
  explicit InputStream(const std::string& path, std::size_t buffer_size = std::size_t{1} << 20);
  // Reads from memory (tests, fuzzers); `name` is used in messages.
  InputStream(std::string name, const void* data, std::size_t size);
  ~InputStream();
  InputStream(const InputStream&) = delete;
  InputStream& operator=(const InputStream&) = delete;

  const std::string& path() const { return path_; }  // as given ("-" for stdin)
  std::string name() const;                          // for messages ("<stdin>" for "-")
  std::optional<uint64_t> size_hint() const { return size_; }
  uint64_t offset() const { return consumed_; }  // bytes consumed so far
  // CRC-32C of every byte consumed so far (the input checksum recorded in .splk metadata).
  uint32_t checksum() const { return crc_; }

  // Up to n bytes (n <= buffer size) without consuming them; fewer only at end of file.
  std::string_view peek(std::size_t n);
  // Exactly n bytes into dst, or throws "unexpected end of file" with `what` as context.
  void read(void* dst, std::size_t n, const char* what = "data");
  // Up to n bytes; returns how many were read (0 at end of file).
  std::size_t read_some(void* dst, std::size_t n);
  // A view of the next n bytes (n <= buffer size) valid until the next call; throws on EOF.
  std::string_view take(std::size_t n, const char* what = "data");
  void skip(uint64_t n, const char* what = "data");
  // One line without its terminator ("\n" or "\r\n"); false at end of file. Throws when a line is
  // longer than max_len (binary junk in a text file).
  bool read_line(std::string& line, std::size_t max_len = std::size_t{1} << 20);
  bool at_eof();

  // Bytes left to the end when the size is known, else nullopt.
  std::optional<uint64_t> remaining() const;

  // From now on, calls fn as bytes are consumed, about every 1 MiB (at most ~1000 times for a
  // file of known size): with offset() / size_hint() and `phase` when the size is known, else
  // with a negative fraction and "read <n> MiB" (how far, on a pipe). An empty fn stops the
  // reports. fn may throw (e.g. Cancelled) to stop reading: the exception leaves the read call
  // that consumed the bytes, and the stream is not read further.
  void set_progress(ProgressFn fn, std::string phase = "reading");

  [[noreturn]] void fail(const std::string& what) const;  // "<name>: byte <offset>: <what>"

 private:
  bool fill(std::size_t want);  // ensures `want` bytes are buffered if the file has them
  void consume(const char* p, std::size_t n);  // advances the offset and the checksum
  // n bytes of a regular file from the descriptor's position into out, in pieces read in
  // parallel (the page cache copies on several cores); fewer only at end of file. Moves the
  // position past them.
  std::size_t read_in_parallel(char* out, std::size_t n);
  static constexpr std::size_t kParallelRead = std::size_t{1} << 23;
  void report_progress();

  std::string path_;
  int fd_ = -1;
  bool owns_fd_ = false;
  std::optional<uint64_t> size_;
  std::vector<char> buf_;
  const char* mem_ = nullptr;  // memory mode: the whole input
  std::size_t begin_ = 0, end_ = 0;
  uint64_t consumed_ = 0;
  uint32_t crc_ = 0;
  bool eof_ = false;
  ProgressFn progress_;
  std::string phase_, progress_text_;
  uint64_t progress_step_ = 0, next_report_ = 0;
};

}  // namespace splatkit
