// CRC-32C (Castagnoli), the checksum of .splk chunks. Hardware instruction when the CPU has
// SSE4.2 (chosen at run time, no -march needed; three interleaved streams, as the instruction's
// latency is three times its issue interval), slicing-by-8 tables otherwise.
#pragma once

#include <cstddef>
#include <cstdint>

namespace splatkit {

// Continues a running CRC: crc32c(crc32c(0, a), b) == crc32c(0, a + b). Buffers of several MB
// are checksummed in parallel pieces whose CRCs are then combined.
uint32_t crc32c(uint32_t crc, const void* data, std::size_t n);

// crc32c by the portable table path only (what CPUs without SSE4.2 run; for the tests).
uint32_t crc32c_portable(uint32_t crc, const void* data, std::size_t n);

// The CRC of a + b from crc_a = crc32c(0, a), crc_b = crc32c(0, b) and b's length.
uint32_t crc32c_combine(uint32_t crc_a, uint32_t crc_b, uint64_t length_b);
// The same call parts a CRC again: crc32c_combine(crc_a, crc32c(0, a + b), |b|) = crc32c(0, b)
// (the CRC of bytes just read, from a running CRC before and after them).

}  // namespace splatkit
