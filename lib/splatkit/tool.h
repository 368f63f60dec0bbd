// The shared frame of every splatkit executable: argument parsing (CLI11), the common options
// (-q, --threads, --version, --help with examples), the one catch that turns exceptions into a
// message "<tool>: <cause>" on stderr and an exit code by class:
//   0 ok, 1 usage, 2 bad input, 3 unsupported, 4 output failure, 5 internal error, 6 out of memory.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

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

  // Parses argv, applies the thread limit, runs `work` and maps failures to exit codes.
  int run(int argc, char** argv, const std::function<void()>& work);

 private:
  std::string name_;
  CLI::App app_;
  bool quiet_ = false;
  int threads_ = 0;
};

}  // namespace splatkit
