#include "render/oiio_images.h"

#include <mutex>

#include "splatkit/error.h"
#include "splatkit/load_module.h"

namespace splatkit::render {

namespace {

// Loads the module, or returns why not.
const OiioImages* load(std::string& why) {
  std::string path;
  void* symbol = load_module(SPLATKIT_OIIO_MODULE_NAME, SPLATKIT_OIIO_MODULE_BUILD_PATH,
                             kOiioImagesEntry, why, path);
  if (symbol == nullptr) return nullptr;
  using Entry = const OiioImages* (*)();
  const OiioImages* images = reinterpret_cast<Entry>(symbol)();
  if (images == nullptr || images->version != kOiioImagesVersion) {
    why = path + " is not this build's module";
    return nullptr;
  }
  return images;
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
