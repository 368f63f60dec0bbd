// The two plain types between a tool's command line and its stage: the files a stage names, and
// what it tells the command line when it is done (kept apart from stage.h so that the CLI frame,
// splatkit/tool.h, needs nothing else of lib/apps).
#pragma once

#include <cstdint>
#include <string>

namespace splatkit::apps {

struct StagePaths {
  std::string input;   // IN: any format read_cloud reads; "-" = standard input; empty = none
  std::string output;  // OUT; "-" = standard output
  std::string report;  // JSON report; empty = none; "-" = standard output
};

// --max-memory and --tmp-dir (Tool::add_memory_options): the process's limit, 0 = none, and where
// its temporary file goes (empty: $TMPDIR, else /tmp).
struct MemoryLimit {
  uint64_t max_bytes = 0;
  std::string tmp_dir;
};

// The summary line's count, unit and extra text: "<tool>: <count> <unit> in <t> s (...), peak RSS
// <m> MiB, <extra>".
struct StageSummary {
  uint64_t count = 0;
  std::string unit = "points";
  std::string extra;
};

}  // namespace splatkit::apps
