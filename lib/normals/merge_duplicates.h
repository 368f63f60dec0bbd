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

#include "splatkit/morton_order.h"
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

// The same merge for a cloud whose positions morton_sort(positions, copies) has rearranged
// (morton_order.h), from the copies it found: they leave `order` and the positions (the others
// keep their sequence, renumbered as merge_duplicates numbers the kept points) and every other
// per-point array (in input order). order, positions and copies are then what merge_duplicates
// followed by morton_sort would have given. Precondition: the cloud has no faces (a mesh is merged
// before it is sorted). Returns the number of points removed.
std::size_t merge_sorted_duplicates(SplatCloud& cloud, std::vector<uint32_t>& order,
                                    const std::vector<DuplicatePoint>& copies);

}  // namespace splatkit
