// libFuzzer target for the OFF reader: any input must either load into a consistent cloud with
// a JSON-serialisable header or throw splatkit::Error; anything else (crash, other exception,
// sanitizer report) is a bug.
#include <cstddef>
#include <cstdint>

#include "formats/off.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  splatkit::InputStream in("fuzz.off", data, size);
  try {
    splatkit::LoadedCloud doc = splatkit::read_off(in);
    doc.cloud.check_consistent();
    (void)doc.header.dump();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
