// Unsigned LEB128 varints and zigzag signed deltas, the integer coding of the graph chunks
// (formats/splk.md: GRPH, CLIP). Writers only plus the zigzag pair; the bounds-checked readers
// live with their decoders, which word the errors for their own chunk.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace splatkit::graph {

// Appends v, 7 bits per byte, low bits first, shortest form (at most 10 bytes).
inline void put_varint(std::vector<uint8_t>& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<uint8_t>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<uint8_t>(v));
}

// Bytes put_varint takes for v (1 to 10).
inline std::size_t varint_size(uint64_t v) {
  return 1 + static_cast<std::size_t>(std::bit_width(v | 1) - 1) / 7;
}

// Writes v at p as put_varint does; returns the byte after it.
inline uint8_t* write_varint(uint8_t* p, uint64_t v) {
  while (v >= 0x80) {
    *p++ = static_cast<uint8_t>(v | 0x80);
    v >>= 7;
  }
  *p++ = static_cast<uint8_t>(v);
  return p;
}

// 0, -1, 1, -2, ... -> 0, 1, 2, 3, ...
inline uint64_t zigzag(int64_t x) {
  return (static_cast<uint64_t>(x) << 1) ^ static_cast<uint64_t>(x >> 63);
}
inline int64_t unzigzag(uint64_t u) {
  return static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1);
}

}  // namespace splatkit::graph
