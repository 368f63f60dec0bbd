// PLY (Stanford polygon format): ascii, binary_little_endian, binary_big_endian. Spec:
// formats/ply.md.
#pragma once

#include <string>
#include <vector>

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

// Streams the vertex element into a SplatCloud (x y z; nx ny nz; radius; red green blue or
// diffuse_*; every other vertex property kept as an ExtraAttribute) and the face element into
// face_offsets/face_indices. Other elements are skipped. header: encoding, elements, comments.
LoadedCloud read_ply(InputStream& in, const ReadOptions& options = {});

enum class PlyEncoding { kBinaryLittleEndian, kBinaryBigEndian, kAscii };

// Writes x y z (float, or double when cloud.origin is non-zero), nx ny nz, radius, colours (uchar
// or ushort by color_bits), the extras with their own types, and faces.
void write_ply(const SplatCloud& cloud, OutputFile& out,
               PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian,
               const std::vector<std::string>& comments = {});

}  // namespace splatkit
