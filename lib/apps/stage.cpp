#include "apps/stage.h"

#include <sys/stat.h>
#include <unistd.h>

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>

#include <algorithm>
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

// The threads the work runs on: --threads above the cores' count still runs one per core (the
// task arena's size).
int thread_count() {
  return static_cast<int>(std::min<std::size_t>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
      static_cast<std::size_t>(tbb::info::default_concurrency())));
}

// Whether two outputs are one: the same file by identity, or both standard output.
bool same_output(const std::string& a, const std::string& b) {
  return same_file(a, b, 1, 1) || (a == "-" && b == "-");
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
    if (same_output(p.output, p.report))
      throw_usage(r + " must not be OUT");
  }
  check_can_create(p.output);
  check_can_create(p.report);
}

void Stage::check_side_output(const std::string& option, const std::string& path) {
  if (path.empty()) return;
  if (!paths_.input.empty() && same_file(paths_.input, path, 0, 1))
    throw_usage(option + " must not be the input file " + input_name_ +
                " (an input is never overwritten)");
  if (same_output(paths_.output, path))
    throw_usage(option + " must not be OUT: " + path);
  if (!paths_.report.empty() && same_output(paths_.report, path))
    throw_usage(option + " must not be the report: " + path);
  for (const auto& [other, other_path] : side_outputs_)
    if (same_output(other_path, path))
      throw_usage(option + " must not be " + other + "'s file: " + path);
  check_can_create(path);
  side_outputs_.emplace_back(option, path);
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

FileFormat Stage::check_output_format(const WriteOptions& options) const {
  FileFormat f = options.format != FileFormat::kUnknown ? options.format
                 : paths_.output == "-"                ? FileFormat::kSplk
                                                       : format_of_extension(paths_.output);
  if (f == FileFormat::kUnknown && is_stream_path(paths_.output)) f = FileFormat::kSplk;
  if (f == FileFormat::kUnknown)
    throw_usage("OUT's extension names no format (.ply, .splk, .xyz, .txt, .pts, .csv, .off, "
                ".las, .laz), and no --format is given: " +
                paths_.output);
  if (options.ascii && options.big_endian)
    throw_usage("--ascii and --big-endian are alternatives");
  // Options for another format than the one written would be ignored: said instead.
  if ((options.ascii || options.big_endian) && f != FileFormat::kPly)
    throw_usage(std::string(options.ascii ? "--ascii" : "--big-endian") +
                " is for PLY output; OUT is " + std::string(format_name(f)));
  if (options.las_format >= 0 && f != FileFormat::kLas && f != FileFormat::kLaz)
    throw_usage("--las-format is for LAS or LAZ output; OUT is " + std::string(format_name(f)));
  if (paths_.output != "-") writable_format(paths_.output, options);
  return f;
}

void Stage::write(const LoadedCloud& doc, const WriteOptions& options, nlohmann::json report,
                  std::span<OutputFile* const> also) {
  const Clock::time_point t0 = Clock::now();
  OutputFile out(paths_.output);
  try {
    write_cloud(doc, out, options);
  } catch (const std::bad_alloc&) {
    throw_out_of_memory("writing " + display_name(paths_.output, true));
  }
  record("write", seconds_since(t0));
  std::vector<OutputFile*> outputs{&out};
  outputs.insert(outputs.end(), also.begin(), also.end());
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
  // Every output written out before any is renamed into place: a full disk fails them all.
  for (OutputFile* out : outputs)
    if (out) out->finish();
  if (file) file->finish();
  for (OutputFile* out : outputs)
    if (out) out->commit();
  if (file) file->commit();
}

}  // namespace splatkit::apps
