// The shared frame of every splatkit executable: argument parsing (CLI11), the common options
// (-q, --threads, --version, --help with examples), the one catch that turns exceptions into a
// message "<tool>: <cause>" on stderr and an exit code by class:
//   0 ok, 1 usage, 2 bad input, 3 unsupported, 4 output failure, 5 internal error, 6 out of memory.
// A tool's main declares its options into an options struct and hands run_stage (or run) the
// one call to its run_<tool> (lib/apps).
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

#include "apps/stage_types.h"
#include "splatkit/progress.h"

namespace splatkit {

class Tool {
 public:
  // `examples` is shown under --help (one example per line, "$ command  # what it does").
  Tool(std::string name, std::string description, std::string examples);
  CLI::App& app() { return app_; }
  const std::string& name() const { return name_; }
  bool quiet() const { return quiet_; }
  // Number of worker threads chosen by --threads (0 in the option = all cores).
  int threads() const { return threads_; }
  // Adds --threads N (only to tools that run parallel work).
  void add_threads_option();
  // --columns: the column layout of text input (ReadOptions::columns).
  void add_columns_option(std::string& columns);
  // --ascii / --big-endian: the PLY encoding (WriteOptions::ascii, big_endian), alternatives.
  void add_ply_encoding_options(bool& ascii, bool& big_endian);
  // Declares the required positionals IN and OUT into paths.input and paths.output.
  void add_in_out(apps::StagePaths& paths, const std::string& in_help, const std::string& out_help);
  // --max-memory SIZE and --tmp-dir DIR into `limit`; run() starts the spill arena
  // (spill_arena.h) with them before the work when a limit is given. `work_help` says how the
  // tool keeps its working set small.
  void add_memory_options(apps::MemoryLimit& limit, const std::string& work_help);
  // By default run() has blocks of 1 MiB and more mapped on their own and handed back when freed,
  // so that the per-point arrays of a finished phase leave the peak RSS (glibc otherwise keeps
  // them in the heap once a large block has been freed). A tool that allocates the same large
  // buffers over and over (splat-view's frames) turns that off: fresh pages each time cost more.
  void reuse_freed_blocks() { map_large_blocks_ = false; }

  // Parses argv, applies the thread limit, runs `work` and maps failures to exit codes. An
  // Error thrown while parsing (by an option's callback) is reported like one from `work`.
  int run(int argc, char** argv, const std::function<void()>& work);

  // run() for a stage: `stage` gets a progress callback (a bar on a terminal, silenced by -q
  // and when `output` — read after parsing — is "-"), and its summary becomes the summary line.
  int run_stage(int argc, char** argv, const std::string& output,
                const std::function<apps::StageSummary(const ProgressFn&)>& stage);

 private:
  std::string name_;
  CLI::App app_;
  bool quiet_ = false;
  int threads_ = 0;
  bool map_large_blocks_ = true;
  apps::MemoryLimit* memory_ = nullptr;
};

// A check for a floating-point option: a finite number in [lo, hi] (CLI::Range lets NaN pass).
CLI::Validator finite_range(double lo, double hi);
// A check for a floating-point option: a finite number > 0.
CLI::Validator positive_finite();

}  // namespace splatkit
