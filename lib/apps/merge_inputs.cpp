#include "apps/merge_inputs.h"

#include "splatkit/error.h"
#include "splatkit/same_file.h"

namespace splatkit::apps {

void check_merge_inputs(const StagePaths& paths, const std::vector<std::string>& more) {
  for (const std::string& in : more) {
    if (in == "-" && paths.input == "-") throw_usage("standard input ('-') given twice");
    if (same_file(in, paths.output, 0, 1))
      throw_usage("OUT is the input file " + in + " (an input is never overwritten)");
    if (!paths.report.empty() && same_file(in, paths.report, 0, 1))
      throw_usage("--report must not be the input file " + in);
  }
}

}  // namespace splatkit::apps
