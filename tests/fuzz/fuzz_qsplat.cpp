// libFuzzer target for the .qs reader: any input must either decode into a consistent tree or
// throw splatkit::Error; anything else (crash, other exception, sanitizer report, a run that is
// not linear in the input) is a bug.
#include <cstddef>
#include <cstdint>
#include <span>

#include "formats/read_qsplat.h"
#include "splatkit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const splatkit::QSplatModel m = splatkit::parse_qsplat(std::span(data, size), "fuzz.qs");
    for (std::size_t i = 0; i < m.size(); ++i)
      if (m.child_count[i] > 0 && m.first_child[i] + m.child_count[i] > m.size()) __builtin_trap();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
