#include "render/oiio_images.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <mutex>

#include "splatkit/error.h"

namespace splatkit::render {

namespace {

// The places to look, in order (oiio_images.h).
std::vector<std::string> candidates() {
  std::vector<std::string> out;
  char exe[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    std::string dir(exe, std::size_t(n));
    dir.erase(dir.find_last_of('/') + 1);
    out.push_back(dir + "../lib/splatkit/" SPLATKIT_OIIO_MODULE_NAME);
  }
  out.push_back(SPLATKIT_OIIO_MODULE_BUILD_PATH);
  return out;
}

// Loads the module, or returns why not.
const OiioImages* load(std::string& why) {
  for (const std::string& path : candidates()) {
    if (::access(path.c_str(), F_OK) != 0) continue;
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      why = ::dlerror();
      return nullptr;
    }
    using Entry = const OiioImages* (*)();
    const auto entry = reinterpret_cast<Entry>(::dlsym(handle, kOiioImagesEntry));
    const OiioImages* images = entry ? entry() : nullptr;
    if (images == nullptr || images->version != kOiioImagesVersion) {
      why = path + " is not this build's module";
      return nullptr;
    }
    return images;  // never closed: OpenImageIO keeps its plugins loaded
  }
  why = "not found beside the executable (../lib/splatkit/" SPLATKIT_OIIO_MODULE_NAME
        ") nor in the build tree";
  return nullptr;
}

}  // namespace

const OiioImages& oiio_images(const std::string& path) {
  static std::string why;
  static const OiioImages* images = nullptr;
  static std::once_flag once;
  std::call_once(once, [] { images = load(why); });
  if (images == nullptr)
    throw_unsupported(display_name(path, true),
                      "images other than PNG need splatkit's OpenImageIO module: " + why);
  return *images;
}

}  // namespace splatkit::render
