// libFuzzer target for the LAS reader on LAZ (LASzip-compressed) input: the LASzip VLR, the chunk
// table and the chunk decoder. Any input must either load into a consistent cloud with a
// JSON-serialisable header or throw splatkit::Error; anything else (crash, other exception,
// sanitizer report) is a bug. Seeds: tests/fuzz/corpus/laz (tests/laz/laz_records make).
#include <cstddef>
#include <cstdint>

#include "formats/las.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  splatkit::InputStream in("fuzz.laz", data, size);
  try {
    splatkit::LoadedCloud doc = splatkit::read_las(in);
    doc.cloud.check_consistent();
    (void)doc.header.dump();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
