// OFF meshes (OFF, COFF, NOFF, CNOFF headers; ascii). Spec: formats/off.md.
#pragma once

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

LoadedCloud read_off(InputStream& in, const ReadOptions& options = {});
void write_off(const SplatCloud& cloud, OutputFile& out);

}  // namespace splatkit
