#include "render/oiio_images.h"

#include "splatkit/error.h"
#include "splatkit/load_module.h"

namespace splatkit::render {

const OiioImages& oiio_images(const std::string& path) {
  std::string why;
  const OiioImages* images =
      loaded_module<OiioImages>(SPLATKIT_OIIO_MODULE_NAME, SPLATKIT_OIIO_MODULE_BUILD_PATH,
                                kOiioImagesEntry, kOiioImagesVersion, why);
  if (images == nullptr)
    throw_unsupported(display_name(path, true),
                      "images other than PNG need splatkit's OpenImageIO module: " + why);
  return *images;
}

}  // namespace splatkit::render
