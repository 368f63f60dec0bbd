// Work split into fixed chunks of an index range [0, n), run in parallel with TBB. The chunks
// depend only on n and the chunk size, never on the thread count, so a result assembled chunk
// by chunk (per-chunk counts and their sums, the first error, partial lists joined in order) is
// the same for any number of threads.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace splatkit {

inline std::size_t chunk_count(std::size_t n, std::size_t chunk) { return (n + chunk - 1) / chunk; }

// fn(c, begin, end) for every chunk c = [c * chunk, min(n, (c + 1) * chunk)), in parallel.
template <class Fn>
void for_each_chunk(std::size_t n, std::size_t chunk, Fn&& fn) {
  tbb::parallel_for(std::size_t{0}, chunk_count(n, chunk),
                    [&](std::size_t c) { fn(c, c * chunk, std::min(n, (c + 1) * chunk)); });
}

// The lowest index i in [0, n) with pred(i), or n if none: chunks in parallel, each stopping at
// its first hit.
template <class Pred>
std::size_t first_in_chunks(std::size_t n, std::size_t chunk, Pred&& pred) {
  std::vector<std::size_t> first(chunk_count(n, chunk), n);
  for_each_chunk(n, chunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (pred(i)) {
        first[c] = i;
        return;
      }
  });
  for (std::size_t i : first)
    if (i < n) return i;
  return n;
}

}  // namespace splatkit
