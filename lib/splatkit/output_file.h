// Atomic output: bytes go to a temporary file `<target>.tmp.XXXXXX` beside the target
// (`.splatkit.tmp.XXXXXX` when the target's name is within 11 bytes of NAME_MAX), renamed over it
// by commit().
//
// A run that fails (exception) leaves no partial file and never clobbers an existing good one: the
// destructor removes the temporary file unless commit() succeeded. A run killed by SIGINT, SIGTERM
// or SIGHUP removes it too (RemoveOnSignal) and dies of the signal. Every failure throws
// Error(kOutput) naming the target and the cause (disk full, broken pipe, permission denied).
//
// What the target may be:
// - "-": standard output (commit() flushes).
// - /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N (e.g. bash's `>(...)`): written through
//   a duplicate of that descriptor, with its offset and flags (`-o /dev/stdout >> log` appends).
// - A FIFO, a character or block device (e.g. /dev/null) or a Unix stream socket: opened and
//   written directly.
//   These two kinds get no temporary file and no rename: a failed run may have written part of
//   the output there.
// - A symbolic link: followed as `cp` does. The temporary file goes beside the link's final
//   target and is renamed over that target; the link stays. A dangling link is refused.
// - An existing regular file: replaced, keeping its permission bits (not set-user/group-ID) and,
//   where the system allows it (as root, or for one's own file), its owner and group. A file the
//   caller may not write is refused ("is write-protected"), as is, for root (whom permissions do
//   not stop), a file with no write permission for anyone (mode 0444 and the like).
// - A directory: refused.
// - Anything else (a new name): created with mode 0666 less the umask.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "splatkit/remove_on_signal.h"

namespace splatkit {

// Whether OutputFile writes `path` as a stream rather than a file: "-", /dev/stdout, /dev/stderr,
// /dev/fd/N, /proc/self/fd/N, an existing FIFO, device or socket (no name to take a format from).
bool is_stream_path(const std::string& path);

class OutputFile {
 public:
  explicit OutputFile(const std::string& path, std::size_t buffer_size = std::size_t{1} << 20);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, std::size_t n);
  void write(std::string_view s) { write(s.data(), s.size()); }
  // Overwrites n of the bytes already written, from `offset` on (e.g. a header's checksum known
  // only at the end). Only when !is_direct(): a temporary file can be written anywhere.
  void write_at(uint64_t offset, const void* data, std::size_t n);
  // Regular temporary files only (!is_direct()): makes the output `size` bytes long (at least
  // the bytes written so far) with its blocks reserved on disk, so that bytes written at their
  // place later cannot fail for want of space. Returns false where the file system reserves no
  // blocks (the caller writes instead); throws when the disk is full. No write() after it.
  bool reserve(uint64_t size);
  // After reserve: write_at for a large range whose bytes are final, around the page cache where
  // the file system allows it (O_DIRECT): the whole blocks of kBlock bytes go straight to the
  // disk when `offset` and `data` are aligned to kBlock, the rest through write_at. Filling the
  // file cache costs more than the disk's bandwidth on some machines (virtual ones whose fresh
  // memory is slow to map). Safe to call from one thread while no other writes.
  static constexpr std::size_t kBlock = 4096;
  void write_through(uint64_t offset, const void* data, std::size_t n);
  uint64_t bytes_written() const { return written_; }
  const std::string& path() const { return path_; }
  bool is_stdout() const { return path_ == "-"; }
  // Whether the bytes go straight to the target (stdout, /dev/fd/N, FIFO, device, socket).
  bool is_direct() const { return temp_path_.empty(); }

  // Flushes and closes (a direct target: flushes): where a full disk or a closed pipe shows. No
  // write after it; the temporary file stays until commit() or the destructor. A caller with
  // several outputs finishes them all before it commits any. Idempotent.
  void finish();
  // finish(), then renames into place. Idempotent.
  void commit();

 private:
  void open_direct(mode_t type);
  void open_temporary(const std::string& target);
  void flush();
  void write_all(const char* p, std::size_t n);
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_, temp_path_, target_path_;  // target_path_: path_ with symlinks resolved
  int fd_ = -1;
  bool owns_fd_ = false;
  bool replaces_ = false;  // an existing regular file: its mode and owner are kept
  mode_t mode_ = 0;
  uid_t uid_ = 0;
  gid_t gid_ = 0;
  std::optional<RemoveOnSignal> remove_on_signal_;  // the temporary file, until commit
  std::vector<char> buf_;
  std::size_t used_ = 0;
  uint64_t written_ = 0;
  bool finished_ = false;
  bool committed_ = false;
  bool reserved_ = false;
  int uncached_fd_ = -1;  // the temporary file again, opened with O_DIRECT
  bool uncached_tried_ = false;
};

}  // namespace splatkit
