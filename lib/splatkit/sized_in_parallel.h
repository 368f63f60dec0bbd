// sized_in_parallel: v.resize(size) for a new, large vector, with its pages mapped in parallel
// first. Shared by the graph builder, the GRPH decoder, the .splk reader and build-qsplat; its page
// mapping also by the SPT encoder's output buffers and (grown_in_parallel) the QSplat tree's levels.
#pragma once

#include <tbb/parallel_for.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace splatkit {

// Maps the whole pages of [begin, end) for writing, in parallel chunks (a hint: what stays
// unmapped is faulted in on first use).
inline void map_pages_in_parallel([[maybe_unused]] const void* begin,
                                  [[maybe_unused]] const void* end) {
#if defined(MADV_POPULATE_WRITE)
  constexpr std::size_t kPage = 4096, kBytes = std::size_t{1} << 22;  // per madvise call
  const auto from = (reinterpret_cast<uintptr_t>(begin) + kPage - 1) & ~(kPage - 1);
  const auto to = reinterpret_cast<uintptr_t>(end) & ~(kPage - 1);
  if (to <= from) return;
  tbb::parallel_for(uintptr_t{0}, (to - from + kBytes - 1) / kBytes, [&](uintptr_t c) {
    const uintptr_t a = from + c * kBytes, b = std::min(to, a + kBytes);
    madvise(reinterpret_cast<void*>(a), b - a, MADV_POPULATE_WRITE);
  });
#endif
}

// v.resize(size) for a vector that grows within the capacity reserved for it, the pages of its
// new part mapped in parallel first.
template <class Vector>  // std::vector or std::basic_string
inline void grown_in_parallel(Vector& v, std::size_t size) {
  map_pages_in_parallel(v.data() + v.size(), v.data() + size);
  v.resize(size);
}

// v.resize(size) for a new, large v: the kernel maps the pages in parallel chunks first, so the
// zeroing in resize does not fault them in one at a time on one thread (a fresh page costs more
// than writing it; the arrays here are tens of MB). The madvise calls are hints only: what stays
// unmapped is faulted in on first use. No huge-page hint: with the kernel's usual "defrag on
// madvise" it may compact memory at the fault, and interleaved runs at 16M splats were as fast or
// faster without it (build-splat-graph median 9.8 against 10.6 s, segment-surfaces 9.5 against
// 9.7 s, splat-view's load 2.45 s against 2.5-5.2 s; build-qsplat at 4M: 1.00 s while free huge
// pages last, 1.5-1.8 s in the first run after another process).
template <class Vector>  // std::vector or std::basic_string
inline void sized_in_parallel(Vector& v, std::size_t size) {
  v.reserve(size);
  grown_in_parallel(v, size);
}

}  // namespace splatkit
