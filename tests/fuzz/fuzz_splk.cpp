// libFuzzer target for read_splk: any input must either decode into a consistent cloud whose
// names and metadata can be shown (splat-info dumps them as JSON) or throw splatkit::Error; any
// other exception, crash, leak, huge allocation or sanitizer report is a bug.
//
// Each input is read twice: as it is (the checksums guard every payload) and with every chunk's
// CRC recomputed, so that mutations also reach the checks made after the checksum (JSON in META,
// NaN positions, face indices) instead of stopping at "checksum mismatch".
#include <cstddef>
#include <cstdint>
#include <vector>

#include "formats/splk.h"
#include "splatkit/crc32c.h"
#include "splatkit/error.h"

namespace {

uint64_t load_le(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}

// Walks the chunk headers after the 16-byte file header and rewrites each payload's CRC-32C.
std::vector<uint8_t> with_valid_checksums(const uint8_t* data, std::size_t size) {
  std::vector<uint8_t> v(data, data + size);
  std::size_t off = 16;
  while (off <= size && size - off >= 20) {
    const uint64_t n = load_le(&v[off + 8], 8);
    if (n > size - off - 20) break;
    const uint32_t crc = splatkit::crc32c(0, &v[off + 20], static_cast<std::size_t>(n));
    for (int i = 0; i < 4; ++i) v[off + 16 + i] = static_cast<uint8_t>(crc >> (8 * i));
    off += 20 + static_cast<std::size_t>(n);
  }
  return v;
}

void read_one(const uint8_t* data, std::size_t size) {
  splatkit::InputStream in("fuzz.splk", data, size);
  try {
    splatkit::LoadedCloud doc = splatkit::read_splk(in);
    doc.cloud.check_consistent();
    nlohmann::json names = nlohmann::json::array();
    for (const auto& e : doc.cloud.extras) names.push_back(e.name);
    (void)names.dump();
    (void)doc.header.dump();
    (void)doc.metadata.dump();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  read_one(data, size);
  const std::vector<uint8_t> fixed = with_valid_checksums(data, size);
  read_one(fixed.data(), fixed.size());
  return 0;
}
