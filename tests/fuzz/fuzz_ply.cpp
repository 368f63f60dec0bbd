// libFuzzer target for read_ply: any input must either decode into a consistent cloud or throw
// splatkit::Error; any other exception, crash, leak or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>

#include "formats/ply.h"
#include "splatkit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  splatkit::InputStream in("fuzz.ply", data, size);
  try {
    splatkit::LoadedCloud doc = splatkit::read_ply(in);
    doc.cloud.check_consistent();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
