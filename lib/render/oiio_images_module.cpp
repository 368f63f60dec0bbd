// splatkit_oiio_images: the module that writes images through OpenImageIO (oiio_images.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <memory>

#include "render/oiio_images.h"

namespace splatkit::render {

namespace {

std::unique_ptr<OIIO::ImageOutput> create_output(const std::string& extension, std::string& why) {
  auto out = OIIO::ImageOutput::create("x." + extension);
  if (!out)
    why = "OpenImageIO cannot write '." + extension + "' images";
  else if (!out->supports("ioproxy"))
    why = "the '." + extension + "' writer of OpenImageIO cannot write to memory; use .png or .exr";
  return why.empty() ? std::move(out) : nullptr;
}

std::string check(const std::string& extension) {
  std::string why;
  create_output(extension, why);
  return why;
}

constexpr int kExrFloatChannels = 8;

bool has_surface_ids(const Framebuffer& f) { return !f.surface_id.empty(); }

OIIO::ImageSpec exr_spec(const Framebuffer& f) {
  const bool ids = has_surface_ids(f);
  OIIO::ImageSpec spec(f.width, f.height, kExrFloatChannels + ids, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z"};
  if (ids) {
    spec.channelnames.push_back("surface_id");
    spec.channelformats.assign(kExrFloatChannels, OIIO::TypeDesc::FLOAT);
    spec.channelformats.push_back(OIIO::TypeDesc::UINT32);
  }
  spec.alpha_channel = 3;
  spec.z_channel = 4;
  spec.attribute("compression", "zip");
  // OpenImageIO stamps EXR files with the current time unless DateTime is set; an empty one keeps
  // the output byte-identical from run to run.
  spec.attribute("DateTime", "");
  return spec;
}

// Pixels in the file's native layout: 8 floats, then the uint32 id when present (4 bytes each,
// so a float vector holds them; the id's bits are copied, not converted).
std::vector<float> interleave_exr(const Framebuffer& f) {
  const std::size_t n = std::size_t(f.width) * f.height;
  const bool ids = has_surface_ids(f);
  const std::size_t stride = kExrFloatChannels + ids;
  std::vector<float> px(n * stride);
  for (std::size_t i = 0; i < n; ++i) {
    float* o = px.data() + stride * i;
    for (int c = 0; c < 4; ++c) o[c] = f.rgba[4 * i + c];
    o[4] = f.depth[i];
    for (int c = 0; c < 3; ++c) o[5 + c] = f.normal[3 * i + c];
    if (ids) std::memcpy(o + kExrFloatChannels, &f.surface_id[i], sizeof(uint32_t));
  }
  return px;
}

std::string encode(const Framebuffer& frame, const std::string& extension, const std::string& name,
                   std::vector<unsigned char>& bytes) {
  std::string why;
  auto out = create_output(extension, why);
  if (!out) return why;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  const bool exr = extension == "exr";
  OIIO::ImageSpec spec =
      exr ? exr_spec(frame) : OIIO::ImageSpec(frame.width, frame.height, 3, OIIO::TypeDesc::UINT8);
  if (!exr) spec.attribute("oiio:ColorSpace", "sRGB");
  if (!out->set_ioproxy(&proxy) || !out->open(name, spec)) return out->geterror();
  bool ok;
  if (exr) {
    std::vector<float> px = interleave_exr(frame);
    // Mixed channel formats: the buffer is in the native per-channel layout (TypeUnknown).
    ok = out->write_image(has_surface_ids(frame) ? OIIO::TypeDesc::UNKNOWN : OIIO::TypeDesc::FLOAT,
                          px.data());
  } else {
    ok = out->write_image(OIIO::TypeDesc::UINT8, frame.rgb8.data());
  }
  if (!ok || !out->close()) {
    const std::string error = out->geterror();
    return error.empty() ? "OpenImageIO failed to write the image" : error;
  }
  return "";
}

const OiioImages kImages{kOiioImagesVersion, check, encode};

}  // namespace

}  // namespace splatkit::render

extern "C" __attribute__((visibility("default"))) const splatkit::render::OiioImages*
splatkit_oiio_images() {
  return &splatkit::render::kImages;
}
