// The .spt file of a Sequential Point Tree [Dachsbacher03] (layout: formats/spt.md): the header,
// and the quantisers of the compact 16-byte entry, encoding and decoding, shared by the writer
// (lib/spt/encode_spt.h) and the reader (read_spt.h).
//
// - Position (3 × 16 bits): q = round((p − box_min) / step) per axis, decoded box_min + q·step in
//   float; error ≤ step/2 per axis (step = box extent / 65535).
// - Normal (16 bits): octahedral map [Meyer10], 8 bits per coordinate; angular error ≤
//   kNormalMaxError.
// - Diameter (16 bits): 0 for 0, else 1..65535 on a logarithmic scale from d_lo to d_hi, rounded
//   up (the decoded diameter is never smaller). The writer adds the position error first, so a
//   decoded disc covers the true disc's projection onto its plane.
// - r_min, r_max (16 bits each): 0 for 0, 65535 for infinity, else 1..65534 on a logarithmic scale
//   from r_lo to r_hi, rounded to nearest. Relative error ≤ (r_hi/r_lo)^(1/131066) − 1. The scale
//   is monotone and a child's r_max is its parent's r_min code, so the intervals stay nested.
// - Colour (16 bits): RGB 5-6-5 rounded to nearest; decoded channels expand to 8 bits.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include "formats/rgb565.h"
#include "splatkit/vec3.h"

namespace splatkit::spt {

inline constexpr char kSptMagic[8] = {'S', 'P', 'L', 'A', 'T', 'S', 'P', 'T'};
inline constexpr uint32_t kSptVersion = 1;
inline constexpr std::size_t kSptHeaderBytes = 128;
inline constexpr uint32_t kSptFlagFull = 1u;   // float entries (40 bytes) instead of 16-byte codes
inline constexpr uint32_t kSptFlagColor = 2u;  // the entries' colours are meaningful
inline constexpr uint32_t kSptKnownFlags = kSptFlagFull | kSptFlagColor;
inline constexpr uint32_t kSptCompactEntryBytes = 16, kSptFullEntryBytes = 40;
inline constexpr uint16_t kRInfinity = 0xFFFF;
// Largest angle (radians) between a unit normal and its decoded code; measured over a dense
// sampling of the sphere (test_formats_read_spt.cpp) at 0.0164 (0.94°).
inline constexpr double kNormalMaxError = 0.017;

// The header's fields (every offset in formats/spt.md), little-endian on disk.
struct SptHeader {
  uint32_t version = kSptVersion;
  uint32_t flags = 0;
  uint32_t entry_bytes = kSptCompactEntryBytes;
  uint32_t depth = 0;  // levels of the builder's tree below the root
  uint64_t entries = 0;
  uint64_t input_points = 0;              // the leaves of the tree
  std::array<double, 3> origin{0, 0, 0};  // added to the local frame gives the file's frame
  Vec3f box_min{0, 0, 0};                 // quantisation frame (local)
  Vec3f step{0, 0, 0};                    // >= 0
  float r_lo = 1, r_hi = 1;               // log scale of r codes, 0 < r_lo <= r_hi
  float d_lo = 1, d_hi = 1;               // log scale of diameter codes, 0 < d_lo <= d_hi
  float epsilon = 0;                      // the build's screen error (radians): r = e_g / epsilon
  float color_weight = 0;                 // the build's colour weight L
  uint32_t checksum = 0;                  // CRC-32C of header bytes 0..123, then the entries
  bool full() const { return (flags & kSptFlagFull) != 0; }
  bool has_color() const { return (flags & kSptFlagColor) != 0; }
};

// Serialises the 128 header bytes (checksum as given).
void write_spt_header(const SptHeader& h, unsigned char* out);
// Reads the fields of the 128 bytes at `in` (no check).
SptHeader read_spt_header(const unsigned char* in);

// A decoded entry, in the local frame.
struct SptEntry {
  Vec3f position{0, 0, 0}, normal{0, 0, 1};
  float diameter = 0, r_min = 0, r_max = 0;  // r_max may be infinity
  std::array<uint8_t, 3> color{0, 0, 0};
};

// Inline: three calls a node, the most frequent code of the writer.
inline uint16_t encode_position(float p, float lo, float step) {
  if (!(step > 0)) return 0;
  const float q = std::floor((p - lo) / step + 0.5f);
  return static_cast<uint16_t>(std::clamp(q, 0.0f, 65535.0f));
}
float decode_position(uint16_t q, float lo, float step);
uint16_t encode_normal(const Vec3f& n);  // n unit
Vec3f decode_normal(uint16_t code);
// A logarithmic code scale from lo (first code) to hi (last code) over `steps` codes, with its
// constants worked out once: built once per file by the writer and the reader (the r scale of
// the header's r_lo, r_hi and the diameter scale of d_lo, d_hi) and passed to the coders below.
struct LogScale {
  double lo = 1, hi = 1;
  int steps = 2;
  double to_position = 0;  // (steps − 1) / ln(hi / lo), 0 when hi <= lo
  double to_value = 0;     // ln(hi / lo) / (steps − 1)
  LogScale() = default;
  LogScale(double lo, double hi, int steps);
  double position(double v) const;  // of v in [lo, hi], as a real in [0, steps − 1]
  double value(double position) const;
};
LogScale r_scale(float r_lo, float r_hi);  // 65534 codes (1..65534)
LogScale d_scale(float d_lo, float d_hi);  // 65535 codes (1..65535)

uint16_t encode_r(float r, const LogScale& s);  // r >= 0 or infinity; s from r_scale
float decode_r(uint16_t code, const LogScale& s);
uint16_t encode_diameter(float d, const LogScale& s);  // d in [0, hi]: decoded >= d; s: d_scale
float decode_diameter(uint16_t code, const LogScale& s);
// encode_diameter for many diameters on one scale: the same codes, with every code's decoded
// diameter worked out once (a writer's millions of splats: no exp per diameter).
class DiameterCoder {
 public:
  explicit DiameterCoder(const LogScale& s);
  uint16_t encode(float d) const;

 private:
  LogScale scale_;
  std::vector<float> decoded_;  // per code
};

// Little-endian helpers for the writer and the reader.
inline void put_u16(unsigned char* p, uint16_t v) {
  p[0] = static_cast<unsigned char>(v);
  p[1] = static_cast<unsigned char>(v >> 8);
}
inline uint16_t get_u16(const unsigned char* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }
void put_u32(unsigned char* p, uint32_t v);
uint32_t get_u32(const unsigned char* p);
void put_f32(unsigned char* p, float v);
float get_f32(const unsigned char* p);

bool looks_like_spt(std::string_view head);  // starts with the magic

}  // namespace splatkit::spt
