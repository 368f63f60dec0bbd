#include "render/write_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <memory>
#include <vector>

#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/output_file.h"

namespace splatkit::render {

namespace {

std::string extension_of(const std::string& path) {
  return path == "-" ? "png" : lower_extension(path);
}

bool is_exr(const std::string& path) { return extension_of(path) == "exr"; }

std::unique_ptr<OIIO::ImageOutput> create_output(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext.empty())
    throw_usage(display_name(path, true) +
                ": no file extension; use .png, .exr or another image extension");
  auto out = OIIO::ImageOutput::create("x." + ext);
  if (!out)
    throw_usage(display_name(path, true) + ": OpenImageIO cannot write '." + ext + "' images");
  if (!out->supports("ioproxy"))
    throw_usage(display_name(path, true) + ": the '." + ext +
                "' writer of OpenImageIO cannot write to memory; use .png or .exr");
  return out;
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

// Rendered frames are large smooth regions and a flat background: the Up filter on every row and
// zlib's run-length strategy (which ignores the level) encode a 1920x1080 frame 4-5x faster than
// libpng's defaults (level 6, a filter chosen per row) for files 10-45 % larger.
void set_fast_png(OIIO::ImageSpec& spec) {
  constexpr int kPngFilterUp = 0x20;  // libpng's PNG_FILTER_UP
  spec.attribute("png:compressionLevel", 1);
  spec.attribute("png:filter", kPngFilterUp);
  spec.attribute("compression", "rle");
}

}  // namespace

FramebufferPlanes planes_for_output(const std::string& path, bool surface_ids) {
  FramebufferPlanes p;
  p.rgb8 = !is_exr(path);
  p.float_color = p.aovs = is_exr(path);
  p.surface_ids = surface_ids && is_exr(path);
  return p;
}

void check_output_format(const std::string& path) { create_output(path); }

void write_image(const Framebuffer& frame, const std::string& path) {
  OutputFile file(path);
  write_image(frame, file);
  file.commit();
}

void write_image(const Framebuffer& frame, OutputFile& file) {
  const std::string& path = file.path();
  auto out = create_output(path);
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  const bool exr = is_exr(path);
  if (exr && (frame.rgba.empty() || frame.depth.empty()))
    throw std::logic_error("write_image: .exr needs the float colour and AOV planes");
  if (!exr && frame.rgb8.empty()) throw std::logic_error("write_image: no 8-bit colour plane");
  OIIO::ImageSpec spec =
      exr ? exr_spec(frame) : OIIO::ImageSpec(frame.width, frame.height, 3, OIIO::TypeDesc::UINT8);
  if (!exr) spec.attribute("oiio:ColorSpace", "sRGB");
  if (extension_of(path) == "png") set_fast_png(spec);
  const std::string name = display_name(path, true);
  if (!out->set_ioproxy(&proxy)) throw_output(name, out->geterror());
  if (!out->open(name, spec)) throw_output(name, out->geterror());
  bool ok;
  if (exr) {
    std::vector<float> px = interleave_exr(frame);
    // Mixed channel formats: the buffer is in the native per-channel layout (TypeUnknown).
    ok = out->write_image(has_surface_ids(frame) ? OIIO::TypeDesc::UNKNOWN : OIIO::TypeDesc::FLOAT,
                          px.data());
  } else {
    ok = out->write_image(OIIO::TypeDesc::UINT8, frame.rgb8.data());
  }
  if (!ok || !out->close()) throw_output(name, out->geterror());
  file.write(bytes.data(), bytes.size());
}

}  // namespace splatkit::render
