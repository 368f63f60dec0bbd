// bucket_scatter: a stable, parallel distribution of n items into buckets, the first step of the
// bucket sorts of the Morton order and of the duplicate merge. The items are cut into at most 64
// blocks (of at least 65536 items); a first pass counts each block's items per bucket, the counts
// become each block's first place in each bucket, and a second pass writes every item to its
// place. Each block writes to as many places at a time as there are buckets, so with a few
// thousand buckets the writes stream (which keeps them fast when the output is paged from disk),
// and every bucket holds its items in input order, whatever the thread count.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace splatkit {

// bucket_of(i): item i's bucket (< buckets); write(i, place): writes item i at `place` of the
// output. Both are called from several threads at once. Returns where each bucket starts in the
// output (buckets + 1 entries, the last n).
template <typename BucketOf, typename Write>
std::vector<std::size_t> bucket_scatter(std::size_t n, std::size_t buckets, BucketOf&& bucket_of,
                                        Write&& write) {
  const std::size_t block = std::max<std::size_t>(std::size_t{1} << 16, (n + 63) / 64);
  const std::size_t blocks = (n + block - 1) / block;
  // Per block and bucket: the count, then the block's next place in the bucket.
  std::vector<std::size_t> next(blocks * buckets, 0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t* count = next.data() + b * buckets;
    for (std::size_t i = b * block, e = std::min(n, i + block); i < e; ++i) ++count[bucket_of(i)];
  });
  std::vector<std::size_t> start(buckets + 1);
  std::size_t sum = 0;
  for (std::size_t d = 0; d < buckets; ++d) {
    start[d] = sum;
    for (std::size_t b = 0; b < blocks; ++b) sum += std::exchange(next[b * buckets + d], sum);
  }
  start[buckets] = sum;
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t* place = next.data() + b * buckets;
    for (std::size_t i = b * block, e = std::min(n, i + block); i < e; ++i)
      write(i, place[bucket_of(i)]++);
  });
  return start;
}

}  // namespace splatkit
