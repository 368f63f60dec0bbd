// release_pages: the whole pages of a range handed back to the system, for a large array whose
// front a pass has finished with while the pass still writes its results: the two are then not
// held in full at the same time.
#pragma once

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <cstdint>

namespace splatkit::graph {

// The pages wholly inside [begin, end) are released: they read as zero afterwards (Linux's
// MADV_DONTNEED on private memory). Partial pages at either end are kept. A hint only: where the
// system has no such call nothing happens, and the memory is freed with its array as before.
inline void release_pages(const void* begin, const void* end) {
#if defined(MADV_DONTNEED)
  constexpr uintptr_t kPage = 4096;
  const uintptr_t from = (reinterpret_cast<uintptr_t>(begin) + kPage - 1) & ~(kPage - 1);
  const uintptr_t to = reinterpret_cast<uintptr_t>(end) & ~(kPage - 1);
  if (to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_DONTNEED);
#else
  (void)begin;
  (void)end;
#endif
}

}  // namespace splatkit::graph
