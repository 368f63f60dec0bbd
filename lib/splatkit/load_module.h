// Loading one of splatkit's plugin modules (shared objects that keep a heavy library, such as
// OpenImageIO, out of the tools' start-up): dlopen, then the module's entry function.
#pragma once

#include <string>

namespace splatkit {

// Looks for the module `file` in ../lib/splatkit/ beside the running executable (an installed
// tool), then at `build_path` (the build tree); loads the first one that exists (never unloaded)
// and returns the address of its symbol `entry`, for the caller to cast to the entry function's
// own type and call (a call through another function type is undefined). On failure returns
// null and sets `why`: not found, dlopen's message, or no such symbol. `path` gets the file
// loaded.
void* load_module(const std::string& file, const std::string& build_path, const char* entry,
                  std::string& why, std::string& path);

}  // namespace splatkit
