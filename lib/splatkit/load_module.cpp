#include "splatkit/load_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <vector>

namespace splatkit {

void* load_module(const std::string& file, const std::string& build_path, const char* entry,
                  std::string& why, std::string& path) {
  std::vector<std::string> candidates;
  char exe[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    std::string dir(exe, std::size_t(n));
    dir.erase(dir.find_last_of('/') + 1);
    candidates.push_back(dir + "../lib/splatkit/" + file);
  }
  candidates.push_back(build_path);
  for (const std::string& candidate : candidates) {
    if (::access(candidate.c_str(), F_OK) != 0) continue;
    path = candidate;
    void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      why = ::dlerror();
      return nullptr;
    }
    void* symbol = ::dlsym(handle, entry);
    if (symbol == nullptr) why = candidate + " is not this build's module";
    return symbol;  // never closed: the libraries behind it keep their plugins loaded
  }
  why = "not found beside the executable (../lib/splatkit/" + file + ") nor in the build tree";
  return nullptr;
}

}  // namespace splatkit
