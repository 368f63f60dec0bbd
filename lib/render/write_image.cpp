#include "render/write_image.h"

#include <stdexcept>
#include <vector>

#include "render/encode_png.h"
#include "render/oiio_images.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/output_file.h"

namespace splatkit::render {

namespace {

// A stream without an extension (stdout, /dev/null, a FIFO) gets PNG.
std::string extension_of(const std::string& path) {
  const std::string ext = path == "-" ? "" : lower_extension(path);
  return ext.empty() && is_stream_path(path) ? "png" : ext;
}

bool is_exr(const std::string& path) { return extension_of(path) == "exr"; }

// The extension, checked: PNG (written without OpenImageIO) or EXR (through it). Other formats
// are refused: their writers are not byte-identical from run to run (TIFF stamps the date) or
// not checked to write valid files from memory (OpenImageIO's TIFF writer there drops the image
// length).
std::string checked_extension(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext.empty()) throw_usage(display_name(path, true) + ": no file extension; use .png or .exr");
  if (ext != "png" && ext != "exr")
    throw_usage(display_name(path, true) + ": images are written as .png or .exr, not ." + ext);
  if (ext != "png") {
    const std::string why = oiio_images(path).check(ext);
    if (!why.empty()) throw_usage(display_name(path, true) + ": " + why);
  }
  return ext;
}

}  // namespace

FramebufferPlanes planes_for_output(const std::string& path, bool surface_ids) {
  FramebufferPlanes p;
  p.rgb8 = !is_exr(path);
  p.float_color = p.aovs = is_exr(path);
  p.surface_ids = surface_ids && is_exr(path);
  return p;
}

void check_output_format(const std::string& path) { checked_extension(path); }

void write_image(const Framebuffer& frame, const std::string& path) {
  OutputFile file(path);
  write_image(frame, file);
  file.commit();
}

void write_image(const Framebuffer& frame, OutputFile& file) {
  const std::string& path = file.path();
  const std::string ext = checked_extension(path);
  if (ext == "exr" && (frame.rgba.empty() || frame.depth.empty()))
    throw std::logic_error("write_image: .exr needs the float colour and AOV planes");
  if (ext != "exr" && frame.rgb8.empty())
    throw std::logic_error("write_image: no 8-bit colour plane");
  if (ext == "png") {
    const std::vector<uint8_t> bytes = encode_png(frame.rgb8.data(), frame.width, frame.height);
    file.write(bytes.data(), bytes.size());
    return;
  }
  const std::string name = display_name(path, true);
  std::vector<unsigned char> bytes;
  const std::string error = oiio_images(path).encode(frame, ext, name, bytes);
  if (!error.empty()) throw_output(name, error);
  file.write(bytes.data(), bytes.size());
}

}  // namespace splatkit::render
