#include "graph/clip_record.h"

#include <stdexcept>
#include <string>

namespace splatkit::graph {

void ClipPartnerTable::check_consistent() const {
  auto fail = [](const std::string& what) { throw std::logic_error("ClipPartnerTable: " + what); };
  if (offsets.empty()) {
    if (!partners.empty() || !flags.empty() || !splat_flags.empty()) fail("no offsets but data");
    return;
  }
  const std::size_t n = num_splats();
  if (offsets[0] != 0) fail("offsets[0] != 0");
  if (offsets.back() != partners.size()) fail("offsets[N] != partner count");
  if (flags.size() != partners.size()) fail("flags and partners differ in size");
  if (splat_flags.size() != n) fail("splat_flags size != N");
  for (std::size_t i = 0; i < n; ++i) {
    if (offsets[i + 1] < offsets[i]) fail("offsets decrease at splat " + std::to_string(i));
    if (splat_flags[i] & ~kClipSplatFlagsKnown) fail("unknown splat flag at " + std::to_string(i));
    for (uint64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      if (partners[k] >= n || partners[k] == i)
        fail("bad partner " + std::to_string(partners[k]) + " of splat " + std::to_string(i));
      if (flags[k] & ~kClipPartnerFlagsKnown) fail("unknown partner flag at " + std::to_string(k));
    }
    if (offsets[i + 1] > offsets[i] && !(flags[offsets[i]] & kClipSubsetStart))
      fail("row of splat " + std::to_string(i) + " does not start a subset");
  }
}

}  // namespace splatkit::graph
