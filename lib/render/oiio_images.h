// OpenImageIO, loaded on first use: splat-view writes every image format but PNG (EXR above all)
// through it. It lives in a module of its own (splatkit_oiio_images, a shared object opened with
// dlopen) because linking OpenImageIO loads its ~230 shared libraries into the process at start-up,
// 0.25-0.4 s per run, which a run writing PNG (encode_png.h) does not need.
//
// The module is looked for in <directory of the executable>/../lib/splatkit/ (the installed
// layout), then where the build tree that compiled this code put it. Both sides are built from the
// same sources by the same compiler, so the interface is C++; kOiioImagesVersion guards against a
// module from another build. Nothing throws across it (std::bad_alloc aside).
#pragma once

#include <string>
#include <vector>

#include "render/framebuffer.h"

namespace splatkit::render {

inline constexpr int kOiioImagesVersion = 1;

struct OiioImages {
  int version = kOiioImagesVersion;
  // "" when OpenImageIO can write images with this extension ("exr", "tif") into memory, else
  // the reason, to follow "<file>: ".
  std::string (*check)(const std::string& extension) = nullptr;
  // Encodes `frame` in the format of `extension` into `bytes`: EXR from the float planes (the
  // channels of write_image.h), any other format from rgb8. Returns "" on success, else
  // OpenImageIO's message; `name` is the file name OpenImageIO's messages use.
  std::string (*encode)(const Framebuffer& frame, const std::string& extension,
                        const std::string& name, std::vector<unsigned char>& bytes) = nullptr;
};

// The module's entry point, exported with C linkage under this name.
inline constexpr const char* kOiioImagesEntry = "splatkit_oiio_images";

// The loaded module (loaded once per process, kept). Throws Error(kUnsupported) naming `path`
// (the image that needs it) when no module can be loaded or its version differs.
const OiioImages& oiio_images(const std::string& path);

}  // namespace splatkit::render
