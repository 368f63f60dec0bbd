// ASPRS LAS 1.0–1.4, uncompressed, point data formats 0–3 (any version) and 6–8 (LAS 1.4).
// Spec: formats/las.md.
#pragma once

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"

namespace splatkit {

// Applies scale and offset (coordinates kept in float64 until the origin is chosen), keeps 16-bit
// RGB (color_bits = 16), intensity/classification/return numbers/gps_time as extras. A LAZ file
// (compressed bit set in the point format, or .laz) throws Error(kUnsupported).
LoadedCloud read_las(InputStream& in, const ReadOptions& options = {});

}  // namespace splatkit
