// Work split into fixed chunks of an index range [0, n), run in parallel with TBB. The chunks
// depend only on n and the chunk size, never on the thread count, so a result assembled chunk
// by chunk (per-chunk counts and their sums, the first error, partial lists joined in order) is
// the same for any number of threads.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>

namespace splatkit {

inline std::size_t chunk_count(std::size_t n, std::size_t chunk) { return (n + chunk - 1) / chunk; }

// fn(c, begin, end) for every chunk c = [c * chunk, min(n, (c + 1) * chunk)), in parallel.
template <class Fn>
void for_each_chunk(std::size_t n, std::size_t chunk, Fn&& fn) {
  tbb::parallel_for(std::size_t{0}, chunk_count(n, chunk),
                    [&](std::size_t c) { fn(c, c * chunk, std::min(n, (c + 1) * chunk)); });
}

}  // namespace splatkit
