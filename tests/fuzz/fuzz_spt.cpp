// libFuzzer target for the .spt reader: any input must either decode into consistent entries or
// throw splatkit::Error; anything else (crash, other exception, sanitizer report, a run that is
// not linear in the input) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "formats/read_spt.h"
#include "splatkit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const splatkit::SptModel m = splatkit::parse_spt(std::span(data, size), "fuzz.spt");
    if (m.r_min.size() != m.size() || m.r_max.size() != m.size()) __builtin_trap();
    for (std::size_t i = 0; i < m.size(); ++i)
      if (!(m.r_min[i] <= m.r_max[i]) || (i > 0 && m.r_max[i] > m.r_max[i - 1])) __builtin_trap();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
