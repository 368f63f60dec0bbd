// merge_duplicates: removes points whose position is exactly equal to an earlier point's.
//
// Exact means bit-equal float coordinates in the local frame (+0 and -0 count as equal). The first
// occurrence (lowest index) of each position is kept with ITS attributes (normal, radius, colour,
// extras); the later copies are dropped with theirs. Kept points stay in their original relative
// order, so a cloud without duplicates is returned unchanged. Face indices are remapped to the kept
// point of their position (faces are kept even if they become degenerate).
//
// Cost: two passes over the positions in order (hash and count, then scatter 20-byte records of
// hash, index and position into at most 4096 buckets), small hash tables per bucket, then a
// linear compaction; 20 bytes per point transient. Nothing reads the cloud at random, so the
// search stays fast when the arrays are paged from disk (--max-memory).
// Deterministic: the result does not depend on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

struct MergeResult {
  std::size_t merged = 0;  // points removed (= input size - output size)
  // For every input point, the index of the output point that now stands for it (#N_in); filled
  // only when the caller asks for it (see merge_duplicates' want_map).
  std::vector<uint32_t> representative;
};

// Merges exact duplicates of `cloud` in place. Precondition: cloud.check_consistent() holds and
// size() < 2^32.
MergeResult merge_duplicates(SplatCloud& cloud, bool want_map = false);

}  // namespace splatkit
