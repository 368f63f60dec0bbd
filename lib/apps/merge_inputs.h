// The inputs of a merging stage (build-spt --merge, build-qsplat --merge): the files after IN,
// checked as splat-convert checks its inputs, and each one read in turn.
#pragma once

#include <string>
#include <vector>

#include "apps/stage.h"
#include "splatkit/input_stream.h"

namespace splatkit::apps {

// Throws Error(kUsage) when one of `more` (the inputs after IN) is standard input as IN is, or
// names OUT or the report, whatever the spelling.
void check_merge_inputs(const StagePaths& paths, const std::vector<std::string>& more);

// Reads every input with `read(InputStream&)` (IN through the stage, then `more`), timed as
// "read"; returns the results in order and their names in `names`.
template <class Model, class Read>
std::vector<Model> read_merge_inputs(Stage& stage, const std::vector<std::string>& more,
                                     std::vector<std::string>& names, Read&& read) {
  std::vector<Model> models;
  models.push_back(
      stage.phase("read", "reading " + stage.input_name(), [&] { return read(stage.input()); }));
  names.push_back(stage.input_name());
  for (const std::string& path : more) {
    InputStream in(path);
    models.push_back(stage.phase("read", "reading " + in.name(), [&] { return read(in); }));
    names.push_back(in.name());
  }
  return models;
}

}  // namespace splatkit::apps
