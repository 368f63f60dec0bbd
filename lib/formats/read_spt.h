// Reading Sequential Point Tree .spt files (layout: formats/spt.md) into decoded entries.
//
// Safe for untrusted input: the header is checked before anything is allocated (magic, version,
// flags, entry size, reserved bytes, finite frame and scales), the entry count must match the
// bytes after the header exactly (so memory is bounded by the file size: 40 bytes per 16-byte
// entry), the checksum must match, and each entry is checked once (finite values, r_min <= r_max,
// the list sorted by r_max descending): linear in the file size. Failures throw Error(kBadInput)
// "<name>: byte <offset>: <what>" with a message per cause; a newer version or unknown flag bits
// throw Error(kUnsupported).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/spt_codes.h"
#include "splatkit/input_stream.h"
#include "splatkit/vec3.h"

namespace splatkit {

struct SptModel {
  spt::SptHeader header;
  uint64_t file_bytes = 0;
  uint64_t leaves = 0;                         // entries with r_min = 0
  std::vector<Vec3f> positions;                // #E disc centres, local frame
  std::vector<Vec3f> normals;                  // #E unit
  std::vector<float> diameters;                // #E
  std::vector<float> r_min, r_max;             // #E, r_max descending (may be infinity)
  std::vector<std::array<uint8_t, 3>> colors;  // #E sRGB 8-bit, or empty
  std::size_t size() const { return positions.size(); }
};

// Decodes the whole file held in `bytes`; `name` is used in messages.
SptModel parse_spt(std::span<const unsigned char> bytes, const std::string& name);
// Reads `in` to its end and decodes it.
SptModel read_spt(InputStream& in);

}  // namespace splatkit
