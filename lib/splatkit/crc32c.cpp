#include "splatkit/crc32c.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#if defined(__x86_64__)
#include <nmmintrin.h>
#endif

namespace splatkit {
namespace {

constexpr uint32_t kPoly = 0x82F63B78u;  // reflected Castagnoli polynomial

// Products of polynomials over GF(2) modulo the CRC polynomial, in the reflected bit order of
// the CRC register (bit 31 is x^0). Shifting a CRC register over n zero bytes multiplies it by
// x^(8n): this is how the CRCs of pieces are joined.
uint32_t multiply_mod(uint32_t a, uint32_t b) {
  uint32_t product = 0;
  for (uint32_t bit = 1u << 31; bit != 0; bit >>= 1) {
    if (a & bit) product ^= b;
    b = (b & 1) ? (b >> 1) ^ kPoly : b >> 1;
  }
  return product;
}

// x^(8 n) modulo the polynomial: x^(2^k) tabulated, multiplied along n's bits.
uint32_t x_pow_8n(uint64_t n) {
  static const std::array<uint32_t, 64> squares = [] {
    std::array<uint32_t, 64> t{};
    t[0] = 1u << 30;  // x^1
    for (std::size_t k = 1; k < t.size(); ++k) t[k] = multiply_mod(t[k - 1], t[k - 1]);
    return t;
  }();
  uint32_t p = 1u << 31;  // x^0
  for (std::size_t k = 3; n != 0; n >>= 1, ++k)  // 8 n = n << 3
    if (n & 1) p = multiply_mod(squares[k % 64], p);
  return p;
}

using Tables = std::array<std::array<uint32_t, 256>, 8>;

Tables make_tables() {
  Tables t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0x82F63B78u & (0u - (c & 1u)));
    t[0][i] = c;
  }
  for (uint32_t i = 0; i < 256; ++i)
    for (int s = 1; s < 8; ++s) t[s][i] = (t[s - 1][i] >> 8) ^ t[0][t[s - 1][i] & 0xFF];
  return t;
}

uint32_t crc32c_soft(uint32_t crc, const unsigned char* p, std::size_t n) {
  static const Tables t = make_tables();
  while (n >= 8) {
    uint64_t v;
    std::memcpy(&v, p, 8);  // little-endian host assumed (x86-64, aarch64)
    v ^= crc;
    crc = t[7][v & 0xFF] ^ t[6][(v >> 8) & 0xFF] ^ t[5][(v >> 16) & 0xFF] ^ t[4][(v >> 24) & 0xFF] ^
          t[3][(v >> 32) & 0xFF] ^ t[2][(v >> 40) & 0xFF] ^ t[1][(v >> 48) & 0xFF] ^ t[0][v >> 56];
    p += 8;
    n -= 8;
  }
  while (n--) crc = (crc >> 8) ^ t[0][(crc ^ *p++) & 0xFF];
  return crc;
}

#if defined(__x86_64__)
__attribute__((target("sse4.2"))) uint64_t crc32c_hw_chain(uint64_t c, const unsigned char* p,
                                                           std::size_t words) {
  for (std::size_t i = 0; i < words; ++i) {
    uint64_t v;
    std::memcpy(&v, p + 8 * i, 8);
    c = _mm_crc32_u64(c, v);
  }
  return c;
}

// Three streams over thirds A, B, D of each round: the register is linear in its start and in
// the bytes read, so reading A from the running register and B and D from 0 gives registers
// a, b, d whose join shift(a, |B D|) ^ shift(b, |D|) ^ d is the register after A B D.
__attribute__((target("sse4.2"))) uint32_t crc32c_hw(uint32_t crc, const unsigned char* p,
                                                     std::size_t n) {
  constexpr std::size_t kLane = 8192;  // bytes per stream and round
  static const uint32_t shift1 = x_pow_8n(kLane), shift2 = x_pow_8n(2 * kLane);
  uint64_t c = crc;
  while (n >= 3 * kLane) {
    uint64_t a = c, b = 0, d = 0;
    for (std::size_t i = 0; i < kLane; i += 8) {
      uint64_t va, vb, vd;
      std::memcpy(&va, p + i, 8);
      std::memcpy(&vb, p + kLane + i, 8);
      std::memcpy(&vd, p + 2 * kLane + i, 8);
      a = _mm_crc32_u64(a, va);
      b = _mm_crc32_u64(b, vb);
      d = _mm_crc32_u64(d, vd);
    }
    c = multiply_mod(shift2, static_cast<uint32_t>(a)) ^
        multiply_mod(shift1, static_cast<uint32_t>(b)) ^ static_cast<uint32_t>(d);
    p += 3 * kLane;
    n -= 3 * kLane;
  }
  c = crc32c_hw_chain(c, p, n / 8);
  p += n / 8 * 8;
  n %= 8;
  uint32_t c32 = static_cast<uint32_t>(c);
  while (n--) c32 = _mm_crc32_u8(c32, *p++);
  return c32;
}
#endif

uint32_t crc32c_serial(uint32_t crc, const unsigned char* p, std::size_t n) {
  crc = ~crc;
#if defined(__x86_64__)
  static const bool hw = __builtin_cpu_supports("sse4.2");
  crc = hw ? crc32c_hw(crc, p, n) : crc32c_soft(crc, p, n);
#else
  crc = crc32c_soft(crc, p, n);
#endif
  return ~crc;
}

}  // namespace

uint32_t crc32c_portable(uint32_t crc, const void* data, std::size_t n) {
  return ~crc32c_soft(~crc, static_cast<const unsigned char*>(data), n);
}

uint32_t crc32c_combine(uint32_t crc_a, uint32_t crc_b, uint64_t length_b) {
  // The pre- and post-inversions of the two CRCs cancel out (as in zlib's crc32_combine).
  return multiply_mod(x_pow_8n(length_b), crc_a) ^ crc_b;
}

uint32_t crc32c(uint32_t crc, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  constexpr std::size_t kPiece = std::size_t{1} << 21;  // bytes per parallel task
  if (n < 4 * kPiece) return crc32c_serial(crc, p, n);
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  std::vector<uint32_t> part(pieces);
  tbb::parallel_for(std::size_t{0}, pieces, [&](std::size_t i) {
    part[i] = crc32c_serial(0, p + i * kPiece, std::min(kPiece, n - i * kPiece));
  });
  for (std::size_t i = 0; i < pieces; ++i)
    crc = crc32c_combine(crc, part[i], std::min(kPiece, n - i * kPiece));
  return crc;
}

}  // namespace splatkit
