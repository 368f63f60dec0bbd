// The decoded form of a splat file that the browser viewer (web/) draws: the library's readers
// decode and check the file (they treat it as untrusted input), and the page receives plain
// little-endian arrays it can hand to WebGL as they are.
//
// Layout ("view model", version 1):
//   bytes 0..7    magic "SKVIEW1\0"
//   bytes 8..11   u32 LE: length J of the JSON header that follows
//   J bytes       JSON (UTF-8): {"kind": "splats" | "spt" | "qsplat", "name", "count", "bounds":
//                 [cx, cy, cz, radius] (the sphere splat-view frames the model by, local frame),
//                 "origin": [x, y, z] (local frame + origin = the file's coordinates),
//                 "mean_radius", kind-specific numbers (below), and "arrays": {NAME: {"offset",
//                 "bytes", "type", "components"}}: each array's byte offset from the start of the
//                 data section}
//   padding       zero bytes up to a multiple of 4
//   data section  the arrays, each starting at a multiple of 4 bytes
// Arrays per kind (f32 = float32, u32 = uint32, LE; colours linear RGB unless said):
//   splats: position f32x3, normal f32x3 (unit), radius f32 (ellipses: the semi-axis along
//           axis), optionally axis f32x3 and minor f32 (elliptic splats), color f32x3,
//           surface u32 and surface_color f32x3 (splat-view's --shade surface palette).
//   spt:    entries: one interleaved vertex buffer, 36 bytes per entry in list order (r_max
//           descending): position f32x3, normal snorm16x3 + 2 zero bytes, diameter f32, r_min
//           f32, r_max f32 (infinity as 3.4e38), sRGB colour u8x4 (alpha 255; when the file has
//           none, 203,203,203: splat-view's grey, and "has_color": false); plus "epsilon" (the
//           build's error, radians) and "leaves".
//   qsplat: centre f32x3, radius f32, normal f32x3 (decoded), cone u32 (2-bit code),
//           first_child u32, child_count u32, roots u32 (#roots), optionally color f32x3; plus
//           "leaves".
#pragma once

#include <string>

namespace splatkit::serve {

// Reads `path` (any splat file splat-view reads: .splk, PLY and the other point formats with
// normals and radii, QSplat .qs, Sequential Point Tree .spt) and returns its view model. `name`
// goes into the JSON and into messages. Throws the readers' Error(kBadInput) on bad input.
std::string encode_view_model(const std::string& path, const std::string& name);

}  // namespace splatkit::serve
