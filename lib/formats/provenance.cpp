#include "formats/provenance.h"

#include <cstdio>

#include "splatkit/error.h"
#include "splatkit/version.h"

namespace splatkit {

nlohmann::json input_record(const InputStream& input, const std::string& format) {
  char crc[9];
  std::snprintf(crc, sizeof crc, "%08x", input.checksum());
  return {{"name", display_name(input.path())},
          {"format", format},
          {"bytes", input.offset()},
          {"crc32c", crc}};
}

nlohmann::json make_provenance(const std::string& tool, const nlohmann::json& options,
                               const InputStream& input, const LoadedCloud& input_doc,
                               const SplatCloud& output) {
  nlohmann::json m;
  m["tool"] = tool;
  m["version"] = kVersion;
  m["options"] = options;
  m["input"] = input_record(input, input_doc.format);
  m["counts"] = {{"points", output.size()}, {"faces", output.face_count()}};
  Bounds b = compute_bounds(output);
  if (!b.empty()) {
    m["bounds"] = {
        {"min",
         {b.min.x + output.origin[0], b.min.y + output.origin[1], b.min.z + output.origin[2]}},
        {"max",
         {b.max.x + output.origin[0], b.max.y + output.origin[1], b.max.z + output.origin[2]}}};
  }
  nlohmann::json history = nlohmann::json::array();
  if (input_doc.metadata.is_object() && !input_doc.metadata.empty()) {
    nlohmann::json previous = input_doc.metadata;
    if (previous.contains("history") && previous["history"].is_array()) {
      history = previous["history"];
      previous.erase("history");
    }
    history.push_back(previous);
  }
  m["history"] = history;
  return m;
}

}  // namespace splatkit
