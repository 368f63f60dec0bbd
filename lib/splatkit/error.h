// Error types shared by the library, the format readers and the tools.
//
// Library code throws splatkit::Error; each tool's main has the one catch that prints
// "<tool>: <message>" on stderr and returns exit_code(kind). Messages carry their context
// (file, line or byte offset, what is wrong) so that a single line tells the user the cause.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace splatkit {

// Exit codes by class, used by every tool.
enum class ErrorKind : int {
  kUsage = 1,        // bad command line (unknown option, missing argument, conflicting options)
  kBadInput = 2,     // malformed, truncated or inconsistent input file
  kUnsupported = 3,  // valid input that splatkit does not handle (LAZ, unknown major version, ...)
  kOutput = 4,       // cannot write the output (permissions, disk full, broken pipe)
  kInternal = 5,     // a bug: an invariant of splatkit's own code did not hold
  kOutOfMemory = 6,  // an allocation failed (the input is too large for this machine's memory)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
};

// "<file>: <what>" — file is the name the user gave ("-" is shown as "<stdin>").
[[noreturn]] void throw_bad_input(const std::string& file, const std::string& what);
[[noreturn]] void throw_unsupported(const std::string& file, const std::string& what);
[[noreturn]] void throw_output(const std::string& file, const std::string& what);
[[noreturn]] void throw_usage(const std::string& what);
// "out of memory while <what>", kind kOutOfMemory: for a std::bad_alloc caught where the work in
// progress can be named. A spill::TempDiskFull (spill_arena.h) becomes kOutput, "no room left in
// the temporary directory ... while <what>".
[[noreturn]] void throw_out_of_memory(const std::string& what);

// The name to show for a path: "<stdin>" / "<stdout>" for "-", else the path itself.
std::string display_name(const std::string& path, bool is_output = false);

}  // namespace splatkit
