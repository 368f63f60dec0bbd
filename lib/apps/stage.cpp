#include "apps/stage.h"

#include <sys/stat.h>
#include <unistd.h>

#include <oneapi/tbb/global_control.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "formats/provenance.h"
#include "formats/splk.h"
#include "splatkit/progress.h"
#include "splatkit/same_file.h"
#include "splatkit/spill_arena.h"

namespace splatkit::apps {

namespace {

int thread_count() {
  return static_cast<int>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace

void check_can_create(const std::string& path) {
  if (path.empty() || path == "-") return;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw_output(path, "is a directory");
    if (!S_ISREG(st.st_mode)) {
      if (::access(path.c_str(), W_OK) != 0)
        throw_output(path, std::string("cannot write: ") + std::strerror(errno));
      return;
    }
  }
  std::string dir = std::filesystem::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw_output(path, std::string("cannot create: ") + std::strerror(errno));
}

Stage::Stage(std::string tool, StagePaths paths, std::string report_option)
    : tool_(std::move(tool)),
      paths_(std::move(paths)),
      input_name_(display_name(paths_.input)),
      start_(Clock::now()) {
  const StagePaths& p = paths_;
  const std::string& r = report_option;
  if (!p.input.empty() && same_file(p.input, p.output, 0, 1))
    throw_usage("OUT is the input file " + input_name_ + " (an input is never overwritten)");
  if (!p.report.empty()) {
    if (!p.input.empty() && same_file(p.input, p.report, 0, 1))
      throw_usage(r + " must not be the input file " + input_name_);
    if (same_file(p.output, p.report, 1, 1) || (p.report == "-" && p.output == "-"))
      throw_usage(r + " must not be OUT");
  }
  check_can_create(p.output);
  check_can_create(p.report);
}

LoadedCloud Stage::read(const ReadOptions& options, const ProgressFn& progress) {
  return phase("read", "reading " + input_name_,
               [&] { return read_cloud(input(), options, progress); });
}

InputStream& Stage::input() {
  if (!in_) in_ = std::make_unique<InputStream>(paths_.input);
  return *in_;
}

void Stage::record(const std::string& key, double seconds) {
  timings_[key] = timings_.value(key, 0.0) + seconds;
}

void Stage::rethrow_with_input_name(const Error& e) const {
  const std::string message = e.what();
  if (e.kind() != ErrorKind::kBadInput || paths_.input.empty() ||
      message.starts_with(input_name_ + ": "))
    throw e;
  throw Error(e.kind(), input_name_ + ": " + message);
}

void Stage::stamp(LoadedCloud& doc, const nlohmann::json& options, bool keep_chunks) {
  options_ = options;
  if (!keep_chunks) drop_chunks_tied_to_splats(doc);
  doc.metadata = make_provenance(tool_, options, *in_, doc, doc.cloud);
}

void Stage::check_output_format(const WriteOptions& options) const {
  if (paths_.output != "-") writable_format(paths_.output, options);
}

void Stage::write(const LoadedCloud& doc, const WriteOptions& options, nlohmann::json report) {
  const Clock::time_point t0 = Clock::now();
  OutputFile out(paths_.output);
  try {
    write_cloud(doc, out, options);
  } catch (const std::bad_alloc&) {
    throw_out_of_memory("writing " + display_name(paths_.output, true));
  }
  record("write", seconds_since(t0));
  OutputFile* outputs[] = {&out};
  commit(outputs, std::move(report));
}

void Stage::commit(std::span<OutputFile* const> outputs, nlohmann::json report) {
  std::unique_ptr<OutputFile> file;
  if (!paths_.report.empty()) {
    report["tool"] = tool_;
    if (!paths_.input.empty()) report["input"] = input_name_;
    report["output"] = display_name(paths_.output, true);
    if (!options_.is_null()) report["options"] = options_;
    report["threads"] = thread_count();
    timings_["command"] = seconds_since(start_);
    for (const auto& [key, seconds] : timings_.items()) report["timings_s"][key] = seconds;
    report["peak_rss_bytes"] = peak_rss_bytes();
    if (spill::active()) {
      const spill::Stats s = spill::stats();
      report["spill"] = {{"max_memory_bytes", s.max_memory},
                         {"temporary_peak_bytes", s.peak_file_bytes},
                         {"trims", s.trims}};
    }
    file = std::make_unique<OutputFile>(paths_.report);
    file->write(report.dump(2) + "\n");
  }
  for (OutputFile* out : outputs) out->commit();
  if (file) file->commit();
}

}  // namespace splatkit::apps
