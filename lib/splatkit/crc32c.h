// CRC-32C (Castagnoli), the checksum of .splk chunks. Hardware instruction when the CPU has
// SSE4.2 (chosen at run time, no -march needed), slicing-by-8 tables otherwise.
#pragma once

#include <cstddef>
#include <cstdint>

namespace splatkit {

// Continues a running CRC: crc32c(crc32c(0, a), b) == crc32c(0, a + b).
uint32_t crc32c(uint32_t crc, const void* data, std::size_t n);

}  // namespace splatkit
