// A Sequential Point Tree's list [Dachsbacher03] as .spt bytes (formats/spt.md).
//
// Sequentialisation: r_min = e_g / epsilon for interior nodes (e_g monotone up the tree, so the
// intervals nest), 0 for leaves; r_max = the parent's r_min, infinity for the root. Entries whose
// interval is empty after quantisation (r_min = r_max: a node with the error of its parent) are
// never drawn and are left out. The list is sorted by r_max descending, ties by node number, so
// the bytes are the same for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "spt/build_spt_tree.h"

namespace splatkit::spt {

struct EncodeSptOptions {
  float epsilon = 1e-3f;   // screen error (radians) the r values are stated for, > 0
  float color_weight = 1;  // stored in the header (the tree already used it)
  bool full = false;       // 40-byte float entries instead of 16-byte codes
  std::array<double, 3> origin{0, 0, 0};
};

struct EncodedSpt {
  std::vector<unsigned char> bytes;
  uint64_t entries = 0;
  uint64_t dropped_empty = 0;           // nodes left out (empty interval)
  std::vector<uint32_t> entry_of_node;  // #nodes: entry index, or kNoParent when left out
                                        // (filled only when asked for, for tests)
};

// `keep_map`: fill entry_of_node.
EncodedSpt encode_spt(const SptTree& tree, const SptInput& input, const EncodeSptOptions& options,
                      bool keep_map = false);

}  // namespace splatkit::spt
