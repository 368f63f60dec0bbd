// Image output, atomically (temporary file renamed into place; see OutputFile) or to standard
// output for "-".
//
// The format follows the extension. .png (and "-") is 8-bit RGB composited over the background,
// sRGB-encoded, written by encode_png.h (for speed: a turntable writes many). .exr is float linear
// colour premultiplied by coverage plus the AOVs with OpenEXR's channel names — R G B A, depth Z
// (camera depth, scene units, +inf where nothing is drawn), world-space unit normal N.X N.Y N.Z,
// and, when the frame has the surface id plane, `surface_id` as a 32-bit unsigned integer channel
// (OpenEXR UINT: ids are exact, which float is not beyond 2^24; 0xFFFFFFFF on background and
// unassigned splats, A tells them apart), written through OpenImageIO, loaded on first use
// (oiio_images.h). Both are byte-identical from run to run; any other extension is refused
// (Error(kUsage)): OpenImageIO's other writers stamp dates (TIFF) or are not checked.
#pragma once

#include <string>

#include "render/framebuffer.h"
#include "splatkit/output_file.h"

namespace splatkit::render {

// The planes a frame must produce for `path`; `surface_ids`: the scene has surface ids (an EXR
// then carries them).
FramebufferPlanes planes_for_output(const std::string& path, bool surface_ids = false);

// Throws Error(kUsage) for an extension other than .png and .exr, Error(kOutput) when writing
// fails (the message names the file and the cause), Error(kUnsupported) when a format other than
// PNG is asked for and OpenImageIO's module cannot be loaded.
void write_image(const Framebuffer& frame, const std::string& path);
// The same into `file` (its path picks the format) without committing it.
void write_image(const Framebuffer& frame, OutputFile& file);

// Throws Error(kUsage) unless `path`'s format is PNG or EXR (checked before rendering),
// Error(kUnsupported) as write_image().
void check_output_format(const std::string& path);

}  // namespace splatkit::render
