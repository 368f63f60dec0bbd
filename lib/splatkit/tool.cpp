#include "splatkit/tool.h"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>

#include <malloc.h>

#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <new>
#include <string>

#include "splatkit/error.h"
#include "splatkit/spill_arena.h"
#include "splatkit/version.h"

namespace splatkit {

namespace {
constexpr uint64_t kMinMaxMemory = uint64_t{64} << 20;  // the tool's own code and libraries: ~30M

// A size with an optional binary unit (K, M, G, T; KB, KiB ...; any case) and a fractional
// number ("1.5G"), rewritten as whole bytes; an error message for anything else.
std::string parse_size(std::string& text) {
  std::size_t end = 0;
  double number = 0;
  try {
    number = std::stod(text, &end);
  } catch (const std::exception&) {
    return "SIZE must be a number of bytes with an optional unit (e.g. 512M, 1.5G): " + text;
  }
  std::string unit;
  for (std::size_t i = end; i < text.size(); ++i)
    if (!std::isspace(static_cast<unsigned char>(text[i])))
      unit += static_cast<char>(std::toupper(static_cast<unsigned char>(text[i])));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
  if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
  const std::string units = "KMGT";
  double scale = 1;
  if (!unit.empty() && unit != "B") {
    const std::size_t k = unit.size() == 1 ? units.find(unit[0]) : std::string::npos;
    if (k == std::string::npos)
      return "SIZE unit must be K, M, G or T (binary: 1K = 1024 bytes): " + text;
    scale = std::ldexp(1.0, 10 * int(k + 1));
  }
  const double bytes = std::round(number * scale);
  if (!(bytes >= 0) || !(bytes < 0x1p64))
    return "SIZE must be a number of bytes from 0 to 2^64: " + text;
  text = std::to_string(static_cast<uint64_t>(bytes));
  return {};
}

bool knows_option(const CLI::App& app, const std::string& name) {
  if (app.get_option_no_throw(name)) return true;
  for (const CLI::App* sub : app.get_subcommands({}))
    if (knows_option(*sub, name)) return true;
  return false;
}

// The first argument that looks like an option ("--name[=value]" or "-x") and that neither the
// tool nor any of its subcommands knows; empty when there is none. CLI11 reports a missing
// positional before an unknown option ("IN is required" for `tool --bogus`): the unknown option
// is the user's real mistake. A tool without required positionals (splat-view: IN and OUT, or
// --serve FILE...) gets an unexpected-argument error instead, with the same real mistake.
std::string unknown_option(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;
    const bool long_name = a.size() > 2 && a.compare(0, 2, "--") == 0;
    const bool short_name =
        a.size() == 2 && a[0] == '-' && std::isalpha(static_cast<unsigned char>(a[1]));
    if (!long_name && !short_name) continue;
    const std::string name = a.substr(0, a.find('='));
    if (!knows_option(app, name)) return name;
  }
  return {};
}
}  // namespace

Tool::Tool(std::string name, std::string description, std::string examples)
    : name_(std::move(name)), app_(std::move(description), name_) {
  app_.set_version_flag("--version", std::string(name_) + " (splatkit) " + kVersion);
  app_.add_flag("-q,--quiet", quiet_, "No progress and no summary line on stderr");
  app_.footer(
      "Examples:\n" + examples +
      "\nExit codes: 0 ok, 1 usage, 2 bad input, 3 unsupported, 4 output failure, "
      "5 internal error, 6 out of memory.\n'-' reads standard input / writes standard output.");
  app_.get_formatter()->column_width(30);
}

void Tool::add_threads_option() {
  app_.add_option("--threads", threads_, "Worker threads (0 = all cores)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            int v = 0;
            if (!CLI::detail::lexical_cast(text, v) || v < 0)
              return "must be 0 (all cores) or a positive number of threads, got " + text;
            return {};
          },
          "NONNEGATIVE"))
      ->default_val(0);
}

void Tool::add_memory_options(apps::MemoryLimit& limit, const std::string& work_help) {
  memory_ = &limit;
  CLI::Option* max =
      app_.add_option(
              "--max-memory", limit.max_bytes,
              "Keep the resident memory under SIZE (e.g. 2G, 1.5G, 512M; at least 64M): the large "
              "arrays live in a temporary file in --tmp-dir, deleted when the tool ends, and "
              "are paged in as the work reaches them. " +
                  work_help)
          ->transform(CLI::Validator(parse_size, "SIZE"));
  app_.add_option("--tmp-dir", limit.tmp_dir,
                  "Directory of --max-memory's temporary file (default: $TMPDIR, else /tmp)")
      ->needs(max);
}

void Tool::add_columns_option(std::string& columns) {
  app_.add_option("--columns", columns,
                  "Column layout of text input, e.g. x,y,z,nx,ny,nz,r,g,b ('_' skips a column)");
}

void Tool::add_ply_encoding_options(bool& ascii, bool& big_endian) {
  auto* ascii_flag = app_.add_flag("--ascii", ascii, "PLY: write ASCII");
  app_.add_flag("--big-endian", big_endian, "PLY: write binary big-endian")->excludes(ascii_flag);
}

void Tool::add_in_out(apps::StagePaths& paths, const std::string& in_help,
                      const std::string& out_help) {
  app_.add_option("IN", paths.input, in_help)->required();
  app_.add_option("OUT", paths.output, out_help)->required();
}

int Tool::run(int argc, char** argv, const std::function<void()>& work) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app_.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app_.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app_.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string unknown =
        dynamic_cast<const CLI::RequiredError*>(&e) || dynamic_cast<const CLI::ExtrasError*>(&e)
            ? unknown_option(app_, argc, argv)
            : std::string();
    // One line, as every error (a script that keeps the first line of stderr keeps it all).
    std::fprintf(stderr, "%s: %s (see %s --help)\n", name_.c_str(),
                 unknown.empty() ? e.what() : ("unknown option " + unknown).c_str(), name_.c_str());
    return static_cast<int>(ErrorKind::kUsage);
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
    return e.exit_code();
  }
  // A closed pipe downstream becomes a write error (exit 4) instead of a silent kill.
  std::signal(SIGPIPE, SIG_IGN);
  // (reuse_freed_blocks in tool.h.) Peak RSS on a 4M random torus: 533 -> 460 MB for
  // estimate-normals, 808 -> 728 MB for build-splat-graph.
  if (map_large_blocks_) mallopt(M_MMAP_THRESHOLD, 1 << 20);
  std::unique_ptr<tbb::global_control> limit;
  if (threads_ > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(threads_));
  else
    threads_ = tbb::info::default_concurrency();
  try {
    if (memory_ && (memory_->max_bytes > 0 || app_.count("--max-memory") > 0)) {
      if (memory_->max_bytes < kMinMaxMemory) throw_usage("--max-memory must be at least 64M");
      spill::start(memory_->max_bytes, memory_->tmp_dir);
    } else if (map_large_blocks_) {
      // Setting the mmap threshold fixes glibc's trim threshold at 128 KiB, so the heap's top
      // was handed back and faulted in again around every short-lived work buffer of a few
      // hundred KiB (the kNN blocks' rows: 4k of estimate-normals' 13k page faults on a 1M
      // torus). The heap then holds blocks under 1 MiB only: it keeps their high-water mark, at
      // most this much. (Not under a memory limit, which counts what the heap keeps.)
      mallopt(M_TRIM_THRESHOLD, 64 << 20);
    }
    work();
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
    return e.exit_code();
  } catch (const spill::TempDiskFull& e) {
    std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
    return static_cast<int>(ErrorKind::kOutput);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: out of memory\n", name_.c_str());
    return static_cast<int>(ErrorKind::kOutOfMemory);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", name_.c_str(), e.what());
    return static_cast<int>(ErrorKind::kInternal);
  }
}

int Tool::run_stage(int argc, char** argv, const std::string& output,
                    const std::function<apps::StageSummary(const ProgressFn&)>& stage) {
  return run(argc, argv, [&] {
    Progress progress(name_, quiet_ || output == "-");
    const apps::StageSummary summary = stage(progress.callback());
    progress.finish(summary.count, summary.unit, summary.extra);
  });
}

CLI::Validator finite_range(double lo, double hi) {
  const std::string range =
      "[" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || v < lo || v > hi)
          return "must be a finite number in " + range + ", got " + text;
        return {};
      },
      "in " + range);
}

CLI::Validator positive_finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || !(v > 0))
          return "must be a finite number > 0, got " + text;
        return {};
      },
      "> 0");
}

}  // namespace splatkit
