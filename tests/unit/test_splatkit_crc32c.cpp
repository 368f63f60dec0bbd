// CRC-32C: published check values, and every path (interleaved hardware streams, parallel pieces
// joined and parted again by crc32c_combine, the portable tables) against a bit-by-bit
// reference.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "splatkit/crc32c.h"

namespace splatkit {
namespace {

// One bit at a time, straight from the definition (reflected polynomial 0x82F63B78).
uint32_t reference_crc(const unsigned char* p, std::size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0x82F63B78u & (0u - (c & 1u)));
  }
  return ~c;
}

std::vector<unsigned char> random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::vector<unsigned char> v(n);
  for (auto& b : v) b = static_cast<unsigned char>(g());
  return v;
}

TEST(Crc32c, PublishedCheckValues) {
  const std::string digits = "123456789";
  EXPECT_EQ(crc32c(0, digits.data(), digits.size()), 0xE3069283u);
  EXPECT_EQ(crc32c_portable(0, digits.data(), digits.size()), 0xE3069283u);
  const std::vector<unsigned char> zeros(32, 0), ones(32, 0xFF);  // RFC 3720, B.4
  EXPECT_EQ(crc32c(0, zeros.data(), zeros.size()), 0x8A9136AAu);
  EXPECT_EQ(crc32c(0, ones.data(), ones.size()), 0x62A8AB43u);
  EXPECT_EQ(crc32c(0, nullptr, 0), 0u);
}

TEST(Crc32c, EveryLengthAndPathMatchesTheReference) {
  // Around the three-stream round (3 x 8192 bytes), the parallel pieces (2 MiB, from 8 MiB on)
  // and odd tails.
  const std::vector<unsigned char> data = random_bytes((std::size_t{17} << 20) + 13, 7);
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{8},
                        std::size_t{24575}, std::size_t{24576}, std::size_t{24577},
                        std::size_t{5 * 24576 + 1003}, (std::size_t{8} << 20) - 1,
                        std::size_t{8} << 20, data.size()}) {
    const uint32_t want = reference_crc(data.data(), n);
    EXPECT_EQ(crc32c(0, data.data(), n), want) << n << " bytes";
    EXPECT_EQ(crc32c_portable(0, data.data(), n), want) << n << " bytes";
  }
}

TEST(Crc32c, RunningCrcsAndCombinedAndSplitPiecesAgree) {
  const std::vector<unsigned char> data = random_bytes(300000, 11);
  const uint32_t whole = reference_crc(data.data(), data.size());
  std::mt19937 g(3);
  for (int t = 0; t < 50; ++t) {
    const std::size_t cut = t == 0 ? 0 : t == 1 ? data.size() : g() % (data.size() + 1);
    const std::size_t rest = data.size() - cut;
    const uint32_t a = crc32c(0, data.data(), cut), b = crc32c(0, data.data() + cut, rest);
    EXPECT_EQ(crc32c(a, data.data() + cut, rest), whole) << "cut at " << cut;
    EXPECT_EQ(crc32c_portable(a, data.data() + cut, rest), whole) << "cut at " << cut;
    EXPECT_EQ(crc32c_combine(a, b, rest), whole) << "cut at " << cut;
    EXPECT_EQ(crc32c_combine(a, whole, rest), b) << "cut at " << cut;
  }
}

}  // namespace
}  // namespace splatkit
