// A Sequential Point Tree's list [Dachsbacher03] as .spt bytes (formats/spt.md).
//
// Sequentialisation: r_min = e_g / epsilon for interior nodes (e_g monotone up the tree, so the
// intervals nest), 0 for leaves; r_max = the parent's r_min, infinity for the root. Entries whose
// interval is empty after quantisation (r_min = r_max: a node with the error of its parent) are
// never drawn and are left out. The list is sorted by r_max descending, ties by node number, so
// the bytes are the same for any thread count.
//
// Compact entries are placed by a counting sort on the 16-bit r_max code and written in slabs
// of a quarter of the list each (a slab's pass reads every node's code but places and encodes
// only the nodes whose code falls in the slab): encoded in place into a file reserved up front,
// or through two buffers, so the list is never whole in memory when the sink can patch the
// header afterwards; otherwise (a pipe) it is one slab. Full-precision lists are sorted and held
// whole.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "splatkit/splat_cloud.h"
#include "spt/build_spt_tree.h"

namespace splatkit::spt {

struct EncodeSptOptions {
  float epsilon = 1e-3f;   // screen error (radians) the r values are stated for, > 0
  float color_weight = 1;  // stored in the header (the tree already used it)
  bool full = false;       // 40-byte float entries instead of 16-byte codes
  std::array<double, 3> origin{0, 0, 0};
};

// Where the bytes go, in order; `patch` (optional) overwrites bytes already written. With patch,
// `reserve(total)` (optional) may make the output `total` bytes long up front (true; false: not
// possible here); the list is then written at its place in large ranges of final bytes, through
// `write_through` when given (ranges and buffers aligned to kSptBlock), else through patch.
inline constexpr std::size_t kSptBlock = 4096;
struct SptSink {
  std::function<void(const unsigned char*, std::size_t)> write;
  std::function<void(uint64_t offset, const unsigned char*, std::size_t)> patch;
  std::function<bool(uint64_t total)> reserve;
  std::function<void(uint64_t offset, const unsigned char*, std::size_t)> write_through;
};

struct EncodedSpt {
  uint64_t entries = 0;
  uint64_t dropped_empty = 0;  // nodes left out (empty interval)
  uint64_t bytes = 0;
  double write_seconds = 0;  // of the time in encode_spt, spent waiting for sink.write
  // Filled only when asked for (tests), indexed by node number (SptTree): the entry of each node
  // (kNoParent when left out) and each node's parent (kNoParent for the root).
  std::vector<uint32_t> entry_of_node, parent;
};

// Encodes and writes the list. The tree's r_min codes are worked out in place (SptRecord::r_min);
// compact lists turn the leaves' parent numbers into r_max codes, write each leaf's other codes
// over its position and release the splats' arrays. `keep_map`: fill entry_of_node and parent.
EncodedSpt encode_spt(SptTree& tree, SptSplats& splats, const EncodeSptOptions& options,
                      const SptSink& sink, bool keep_map = false);

// The whole build in memory (tests and small clouds): sort, tree, list. With `keep_map`, the
// map's leaves are numbered by their index in `cloud`. `frame`: as sort_spt_splats's (a survey's
// box for a tile of it), holding every position.
struct SptBytes {
  std::vector<unsigned char> bytes;
  EncodedSpt info;
  uint32_t depth = 0;
};
SptBytes build_spt_bytes(const SplatCloud& cloud, float color_weight,
                         const EncodeSptOptions& options, bool keep_map = false,
                         const Bounds* frame = nullptr);

}  // namespace splatkit::spt
