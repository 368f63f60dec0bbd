#include "apps/run_splat_info.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <ostream>

#include "apps/describe_terrain_file.h"
#include "formats/describe_cloud.h"
#include "formats/describe_qsplat.h"
#include "formats/describe_spt.h"
#include "formats/read_qsplat.h"
#include "formats/read_spt.h"
#include "splatkit/error.h"

namespace splatkit::apps {

namespace {

nlohmann::json describe(const std::string& path, const ReadOptions& read) {
  try {
    if (nlohmann::json terrain = describe_terrain_file(path); !terrain.is_null()) return terrain;
    InputStream in(path);
    if (looks_like_qsplat(in.peek(6))) return describe_qsplat(read_qsplat(in), path);
    if (spt::looks_like_spt(in.peek(8))) return describe_spt(read_spt(in), path);
    auto bytes = in.size_hint();
    const LoadedCloud doc = read_cloud(in, read);
    if (!bytes) bytes = in.offset();
    return describe_cloud(doc, path, bytes);
  } catch (const std::bad_alloc&) {
    throw_out_of_memory("reading " + display_name(path));
  }
}

}  // namespace

void run_splat_info(const SplatInfoOptions& o, std::ostream& out, std::ostream& err) {
  nlohmann::json reports = nlohmann::json::array();
  std::optional<Error> first_failure;
  std::size_t failures = 0, printed = 0;
  for (const std::string& file : o.files) {
    nlohmann::json report;
    try {
      report = describe(file, o.read);
    } catch (const Error& e) {
      if (o.files.size() == 1) throw;
      err << "splat-info: " << e.what() << "\n";
      if (!first_failure) first_failure = e;
      ++failures;
      continue;
    }
    if (o.json) {
      reports.push_back(std::move(report));
    } else {
      if (printed++ > 0) out << "\n";
      const std::string format = report.value("format", "");
      out << (format == "qs"                             ? describe_qsplat_text(report)
              : format == "spt"                          ? describe_spt_text(report)
              : format == "ham" || format == "heightmap" ? describe_terrain_text(report)
                                                         : describe_cloud_text(report));
    }
  }
  if (o.json) out << (o.files.size() == 1 ? reports[0] : reports).dump(2) << "\n";
  errno = 0;
  out.flush();
  if (!out)  // the stream keeps no cause; the failed write(2) left it in errno (EPIPE: `| head`)
    throw_output("-", std::string("cannot write the report") +
                          (errno ? std::string(": ") + std::strerror(errno) : std::string()));
  if (first_failure)
    throw Error(first_failure->kind(), std::to_string(failures) + " of " +
                                           std::to_string(o.files.size()) +
                                           " files could not be described");
}

}  // namespace splatkit::apps
