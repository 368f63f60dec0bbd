// .splk, splatkit's own container. Spec: splk.md.
#pragma once

#include <string_view>

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

// The 16-byte file magic at offset 0.
bool is_splk_magic(std::string_view first_bytes);

// Reads every chunk: META into doc.metadata, SPLT into doc.cloud, any other chunk (known to a
// later stage, or unknown) into doc.chunks in file order. Checks every size and checksum.
LoadedCloud read_splk(InputStream& in, const ReadOptions& options = {});

// Writes META (doc.metadata), SPLT (doc.cloud), then doc.chunks in order, then END.
void write_splk(const LoadedCloud& doc, OutputFile& out);

}  // namespace splatkit
