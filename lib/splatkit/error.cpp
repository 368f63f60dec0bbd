#include "splatkit/error.h"

#include <exception>

#include "splatkit/spill_arena.h"

namespace splatkit {

std::string display_name(const std::string& path, bool is_output) {
  if (path == "-") return is_output ? "<stdout>" : "<stdin>";
  return path;
}

void throw_bad_input(const std::string& file, const std::string& what) {
  throw Error(ErrorKind::kBadInput, display_name(file) + ": " + what);
}

void throw_unsupported(const std::string& file, const std::string& what) {
  throw Error(ErrorKind::kUnsupported, display_name(file) + ": " + what);
}

void throw_output(const std::string& file, const std::string& what) {
  throw Error(ErrorKind::kOutput, display_name(file, true) + ": " + what);
}

void throw_usage(const std::string& what) { throw Error(ErrorKind::kUsage, what); }

void throw_out_of_memory(const std::string& what) {
  try {  // (called from a handler: a full spill file is a disk problem, not a memory one)
    if (const std::exception_ptr e = std::current_exception()) std::rethrow_exception(e);
  } catch (const spill::TempDiskFull& full) {
    throw Error(ErrorKind::kOutput, std::string(full.what()) + " while " + what);
  } catch (...) {
  }
  throw Error(ErrorKind::kOutOfMemory, "out of memory while " + what);
}

}  // namespace splatkit
