// Loading one of splatkit's plugin modules (shared objects that keep a heavy library, such as
// OpenImageIO, out of the tools' start-up): dlopen, then the module's entry function.
#pragma once

#include <string>

namespace splatkit {

// Looks for the module `file` in ../lib/splatkit/ beside the running executable (an installed
// tool), then at `build_path` (the build tree); loads the first one that exists (never unloaded)
// and returns what its entry function `entry` (no arguments, returning a pointer) returns. On
// failure returns null and sets `why`: not found, dlopen's message, or no entry function (or
// one that returns null).
// `path` gets the file loaded.
const void* load_module(const std::string& file, const std::string& build_path, const char* entry,
                        std::string& why, std::string& path);

}  // namespace splatkit
