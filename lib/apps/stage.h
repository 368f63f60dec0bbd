// Stage: the frame every splatkit stage shares around its algorithm, so that each run_<tool>
// holds only its own work. In order of use:
//   1. the constructor checks the paths before any work: OUT and the report never name the input
//      or each other, whatever the spelling (same_file.h: device + inode), and both can be
//      created (the directory exists and is writable, the path is not a directory);
//   2. read() reads IN and times it;
//   3. phase() runs and times a step of the work, naming it when memory runs out;
//   4. stamp() records the options and the provenance (formats/provenance.h) in the document;
//   5. write() / commit() writes OUT and the JSON report, committing OUT only once the report is
//      written: a failing report leaves OUT as it was.
// The report skeleton: "tool", "input", "output", "options", "threads", "timings_s" (each phase,
// "write" and "command", in seconds) and "peak_rss_bytes", merged into the stage's own fields.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <new>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "apps/stage_types.h"
#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "formats/write_cloud.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/output_file.h"
#include "splatkit/seconds_since.h"

namespace splatkit::apps {

// The checks OutputFile would fail on, made before the work (Error(kOutput) naming `path`): a
// directory, a missing or unwritable parent directory, an existing special file (FIFO, device)
// that cannot be written. "-" and "" pass.
void check_can_create(const std::string& path);

class Stage {
 public:
  // `report_option` names the report in messages ("--report", "--stats"). Throws Error(kUsage)
  // when OUT or the report names IN, or the report names OUT (both "-" included); Error(kOutput)
  // when OUT or the report cannot be created.
  Stage(std::string tool, StagePaths paths, std::string report_option = "--report");

  const std::string& tool() const { return tool_; }
  const StagePaths& paths() const { return paths_; }
  const std::string& input_name() const { return input_name_; }  // "<stdin>" for "-"

  // Reads IN, timed as "read", reporting the bytes read to `progress` (read_cloud.h). A
  // std::bad_alloc becomes Error(kOutOfMemory) naming IN.
  LoadedCloud read(const ReadOptions& options = {}, const ProgressFn& progress = no_progress());

  // IN, opened on first use (read() reads from it): for a stage that looks at the first bytes
  // (InputStream::peek) or reads a format other than a cloud (a QSplat .qs file).
  InputStream& input();

  // Runs `work()`, timed under `key` (nullptr: not timed): a std::bad_alloc becomes
  // Error(kOutOfMemory) "out of memory while <doing>", and a bad-input error whose message lacks
  // IN's name gets it in front.
  template <class Work>
  decltype(auto) phase(const char* key, const std::string& doing, Work&& work) {
    const Clock::time_point t0 = Clock::now();
    struct Record {
      Stage& stage;
      const char* key;
      Clock::time_point t0;
      ~Record() {
        if (key != nullptr) stage.record(key, seconds_since(t0));
      }
    } record{*this, key, t0};
    try {
      return work();
    } catch (const std::bad_alloc&) {
      throw_out_of_memory(doing);
    } catch (const Error& e) {
      rethrow_with_input_name(e);
    }
  }

  // Adds `seconds` to the report's timings_s[key]; seconds(key): the time recorded so far.
  void record(const std::string& key, double seconds);
  double seconds(const std::string& key) const { return timings_.value(key, 0.0); }

  // Records `options` (the report's "options") and sets doc.metadata to this stage's provenance;
  // drops the chunks tied to the splats first (an earlier graph indexes other splats) unless
  // `keep_chunks`.
  void stamp(LoadedCloud& doc, const nlohmann::json& options, bool keep_chunks = false);

  // Checks that OUT can be written with `options` before the work and returns its format:
  // Error(kUsage) when neither options.format nor OUT's extension names a format, or for options
  // of another format (--ascii for LAS, ...); Error(kUnsupported) for PCD.
  FileFormat check_output_format(const WriteOptions& options) const;

  // Checks a side output given by `option` (e.g. "--outliers-out") before the work: Error(kUsage)
  // when it names IN, OUT, the report or an earlier side output, whatever the spelling;
  // Error(kOutput) when it cannot be created. "" passes.
  void check_side_output(const std::string& option, const std::string& path);

  // Writes doc to OUT, then commit() with OUT and `also` (side outputs written, not committed).
  void write(const LoadedCloud& doc, const WriteOptions& options, nlohmann::json report = {},
             std::span<OutputFile* const> also = {});

  // Writes the report (when a path is set): the skeleton merged into `report`; then finishes
  // `outputs` (written, not yet committed; null entries skipped) and the report, so that a full
  // disk fails before any is in place, and commits them in order, the report last.
  void commit(std::span<OutputFile* const> outputs, nlohmann::json report = {});

 private:
  [[noreturn]] void rethrow_with_input_name(const Error& e) const;

  std::string tool_;
  StagePaths paths_;
  std::string input_name_;
  std::unique_ptr<InputStream> in_;
  std::vector<std::pair<std::string, std::string>> side_outputs_;  // (option, path)
  nlohmann::json options_;
  nlohmann::json timings_ = nlohmann::json::object();
  Clock::time_point start_;
};

}  // namespace splatkit::apps
