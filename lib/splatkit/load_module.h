// Loading one of splatkit's plugin modules (shared objects that keep a heavy library, such as
// OpenImageIO, out of the tools' start-up): dlopen, then the module's entry function.
#pragma once

#include <mutex>
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

// A module's interface, loaded once per process: load_module, then its entry function (taking
// nothing, returning const Module*) called and the interface's `version` member checked against
// `version`. Null when that failed, with `why` (the same on every later call). The result is kept
// per Module type: one module per interface type, always asked for with the same arguments.
template <class Module>
const Module* loaded_module(const char* file, const char* build_path, const char* entry,
                            int version, std::string& why) {
  static std::string failure;
  static const Module* module = nullptr;
  static std::once_flag once;
  std::call_once(once, [&] {
    std::string path;
    void* symbol = load_module(file, build_path, entry, failure, path);
    if (symbol == nullptr) return;
    using Entry = const Module* (*)();
    const Module* loaded = reinterpret_cast<Entry>(symbol)();
    if (loaded == nullptr || loaded->version != version)
      failure = path + " is not this build's module";
    else
      module = loaded;
  });
  why = failure;
  return module;
}

}  // namespace splatkit
