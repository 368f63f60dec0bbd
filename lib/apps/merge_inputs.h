// The inputs of a merging stage (build-spt --merge, build-qsplat --merge): the files after IN,
// checked as splat-convert checks its inputs, and each one read in turn.
#pragma once

#include <new>
#include <string>
#include <vector>

#include "apps/stage.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/seconds_since.h"

namespace splatkit::apps {

// Throws Error(kUsage) when one of `more` (the inputs after IN) is standard input as IN is, or
// names OUT or the report, whatever the spelling.
void check_merge_inputs(const StagePaths& paths, const std::vector<std::string>& more);

// Reads every input with `read(InputStream&)` (IN through the stage, then `more`), timed as
// "read"; returns the results in order and their names in `names`. Errors name the file they
// come from (the stage would put IN's name in front of the others').
template <class Model, class Read>
std::vector<Model> read_merge_inputs(Stage& stage, const std::vector<std::string>& more,
                                     std::vector<std::string>& names, Read&& read) {
  std::vector<Model> models;
  models.push_back(
      stage.phase("read", "reading " + stage.input_name(), [&] { return read(stage.input()); }));
  names.push_back(stage.input_name());
  for (const std::string& path : more) {
    const Clock::time_point t0 = Clock::now();
    InputStream in(path);
    try {
      models.push_back(read(in));
    } catch (const std::bad_alloc&) {
      throw_out_of_memory("reading " + in.name());
    }
    stage.record("read", seconds_since(t0));
    names.push_back(in.name());
  }
  return models;
}

// Runs `work()` (a merge whose errors name their file), timed as `key`; out of memory becomes
// Error(kOutOfMemory) "out of memory while <doing>".
template <class Work>
decltype(auto) merge_phase(Stage& stage, const char* key, const std::string& doing, Work&& work) {
  const Clock::time_point t0 = Clock::now();
  try {
    decltype(auto) result = work();
    stage.record(key, seconds_since(t0));
    return result;
  } catch (const std::bad_alloc&) {
    throw_out_of_memory(doing);
  }
}

}  // namespace splatkit::apps
