// The metadata a tool records in the .splk files it writes: who made the file, from what, how.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "formats/loaded_cloud.h"
#include "splatkit/input_stream.h"

namespace splatkit {

// {"tool", "version", "options", "input": {"name", "bytes", "crc32c"}, "counts", "bounds",
//  "history": [...]} — `history` holds the metadata of the input's own producers (oldest first),
// so a file tells its whole pipeline. Call after the input was read to its end (the checksum
// covers the bytes consumed). Deterministic: no timings, no dates.
// {"name", "format", "bytes", "crc32c"} of an input read to its end (the checksum covers the bytes
// consumed): the "input" of the provenance, and of the lists of inputs that splat-tile and
// splat-convert record.
nlohmann::json input_record(const InputStream& input, const std::string& format);

nlohmann::json make_provenance(const std::string& tool, const nlohmann::json& options,
                               const InputStream& input, const LoadedCloud& input_doc,
                               const SplatCloud& output);

}  // namespace splatkit
