// Pieces shared by LASzip's point-wise (version 2) and layered (version 3) item models: the
// streaming median of the coordinate differences, lazily created byte-indexed models, and
// two's-complement arithmetic on 32-bit values. Spec: formats/laz.md.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "formats/laz_arithmetic.h"

namespace splatkit::laz {

// Median of the last five values, updated in O(1) (LASzip's StreamingMedian5).
struct Median5 {
  std::array<int32_t, 5> v{};
  bool high = true;
  int32_t get() const { return v[2]; }
  void add(int32_t x) {
    if (high) {
      if (x < v[2]) {
        v[4] = v[3];
        v[3] = v[2];
        if (x < v[0]) {
          v[2] = v[1];
          v[1] = v[0];
          v[0] = x;
        } else if (x < v[1]) {
          v[2] = v[1];
          v[1] = x;
        } else {
          v[2] = x;
        }
      } else {
        if (x < v[3]) {
          v[4] = v[3];
          v[3] = x;
        } else {
          v[4] = x;
        }
        high = false;
      }
    } else {
      if (v[2] < x) {
        v[0] = v[1];
        v[1] = v[2];
        if (v[4] < x) {
          v[2] = v[3];
          v[3] = v[4];
          v[4] = x;
        } else if (v[3] < x) {
          v[2] = v[3];
          v[3] = x;
        } else {
          v[2] = x;
        }
      } else {
        if (v[1] < x) {
          v[0] = v[1];
          v[1] = x;
        } else {
          v[0] = x;
        }
        high = true;
      }
    }
  }
};

// Lazily created 256-symbol models indexed by a byte (LASzip creates them on first use).
struct LazyModels {
  std::array<std::unique_ptr<SymbolModel>, 256> m;
  SymbolModel& operator[](unsigned i) {
    if (!m[i]) m[i] = std::make_unique<SymbolModel>(256);
    return *m[i];
  }
};

inline int32_t wrap_add(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
}
inline int32_t wrap_sub(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) - static_cast<uint32_t>(b));
}
inline int32_t wrap_mul(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(static_cast<int64_t>(a) * b));
}
inline unsigned clamp_u8(int v) { return v < 0 ? 0u : v > 255 ? 255u : static_cast<unsigned>(v); }

}  // namespace splatkit::laz
