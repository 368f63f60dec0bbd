// RGB 5-6-5 colour words, as .qs and .spt nodes store them (formats/qsplat.md, formats/spt.md).
//
// The decoder expands each channel to 8 bits by repeating its high bits (v << 3 | v >> 2 for red
// and blue, v << 2 | v >> 4 for green); the encoder takes, per channel, the code whose expansion is
// nearest to the 8-bit value: at most 4 off in red and blue, 2 in green (truncation, v >> 3,
// darkens dark values and brightens light ones by up to 7: 200 comes back as 206, 71 as 66).
#pragma once

#include <array>
#include <cstdint>

namespace splatkit {

inline uint16_t encode_rgb565(const std::array<uint8_t, 3>& c) {
  const int r = (c[0] * 31 + 127) / 255, g = (c[1] * 63 + 127) / 255, b = (c[2] * 31 + 127) / 255;
  return static_cast<uint16_t>(r << 11 | g << 5 | b);
}

inline std::array<uint8_t, 3> decode_rgb565(uint16_t c) {
  const unsigned r = c >> 11, g = (c >> 5) & 63u, b = c & 31u;
  return {static_cast<uint8_t>(r << 3 | r >> 2), static_cast<uint8_t>(g << 2 | g >> 4),
          static_cast<uint8_t>(b << 3 | b >> 2)};
}

}  // namespace splatkit
