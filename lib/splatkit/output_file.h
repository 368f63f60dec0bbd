// Atomic output: bytes go to a temporary file beside the target, renamed over it by commit().
//
// A run that fails (exception, signal before commit) leaves no partial file and never clobbers an
// existing good one: the destructor removes the temporary file unless commit() succeeded.
// "-" streams to standard output (commit() flushes). Writes are buffered; every failure throws
// Error(kOutput) naming the target and the cause (disk full, broken pipe, permission denied).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace splatkit {

class OutputFile {
 public:
  explicit OutputFile(const std::string& path, std::size_t buffer_size = std::size_t{1} << 20);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, std::size_t n);
  void write(std::string_view s) { write(s.data(), s.size()); }
  uint64_t bytes_written() const { return written_; }
  const std::string& path() const { return path_; }
  bool is_stdout() const { return path_ == "-"; }

  // Flushes, closes and renames into place (file mode 0644 less the umask). Idempotent.
  void commit();

 private:
  void flush();
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_, temp_path_;
  int fd_ = -1;
  std::vector<char> buf_;
  std::size_t used_ = 0;
  uint64_t written_ = 0;
  bool committed_ = false;
};

}  // namespace splatkit
