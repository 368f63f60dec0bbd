// Image output through OpenImageIO, atomically (temporary file renamed into place; see
// OutputFile) or to standard output for "-".
//
// The format follows the extension: .exr writes float linear colour premultiplied by coverage
// plus the AOVs with OpenEXR's channel names — R G B A, depth Z (camera depth, scene units,
// +inf where nothing is drawn), world-space unit normal N.X N.Y N.Z, and, when the frame has the
// surface id plane, `surface_id` as a 32-bit unsigned integer channel (OpenEXR UINT: ids are
// exact, which float is not beyond 2^24; 0xFFFFFFFF on background and unassigned splats, A tells
// them apart); any other extension that
// OpenImageIO writes (.png default, .jpg, .tif, .bmp, ...) gets 8-bit RGB composited over the
// background, sRGB-encoded. "-" writes PNG. PNG is written for speed (a turntable writes many):
// compression level 1, the Up filter on every row, zlib's run-length strategy.
#pragma once

#include <string>

#include "render/framebuffer.h"
#include "splatkit/output_file.h"

namespace splatkit::render {

// The planes a frame must produce for `path`; `surface_ids`: the scene has surface ids (an EXR
// then carries them).
FramebufferPlanes planes_for_output(const std::string& path, bool surface_ids = false);

// Throws Error(kUsage) for an extension OpenImageIO cannot write, Error(kOutput) when writing
// fails (the message names the file and the cause).
void write_image(const Framebuffer& frame, const std::string& path);
// The same into `file` (its path picks the format) without committing it.
void write_image(const Framebuffer& frame, OutputFile& file);

// Throws Error(kUsage) unless OpenImageIO can write `path`'s format (checked before rendering).
void check_output_format(const std::string& path);

}  // namespace splatkit::render
