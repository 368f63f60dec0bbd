// The replaceable global allocation functions of an executable that may spill (spill_arena.h):
// blocks of spill::kMinBlock bytes and more come from the arena once it is started; everything
// else, and everything before it starts, from malloc. Linked into the executables as an object
// (not from an archive, where the C++ runtime's definitions could win), and left out of sanitizer
// builds, whose runtime replaces these functions itself.
//
// Large blocks from malloc are aligned to 2 MiB and advised for transparent huge pages
// (MADV_HUGEPAGE, which the kernel's default "madvise" mode honours): the tools map such blocks
// afresh (tool.cpp sets malloc's mmap threshold) and fill them once, and with 4 KiB pages the page
// faults took a fifth of estimate-normals' time on a 1M-point cloud (AMD EPYC VM, 2 threads:
// task-clock 1.68 -> 1.16 s, page faults 47.6k -> 1.9k with tool.cpp's trim threshold; peak RSS
// 84 -> 88 bytes/point). Not while the arena runs: there resident memory is what is budgeted,
// and a huge page makes a block resident 2 MiB at a time.
#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "splatkit/spill_arena.h"

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kHugeMin = kHugePage;

// A block of n >= kHugeMin bytes on 2 MiB boundaries, advised for huge pages; nullptr when the
// arena runs, n is smaller, or the allocation fails (the caller then allocates as usual). The
// alignment costs address space only: the untouched head of the mapping is never resident.
void* allocate_huge(std::size_t n) {
  if (n < kHugeMin || splatkit::spill::active()) return nullptr;
  // Whole huge pages, so that the mapping holds the last one too (its tail is never touched).
  const std::size_t size = (n + kHugePage - 1) & ~(kHugePage - 1);
  void* p = nullptr;
  if (::posix_memalign(&p, kHugePage, size) != 0) return nullptr;
  ::madvise(p, size, MADV_HUGEPAGE);  // advice: failure is harmless
  return p;
}

void* allocate(std::size_t n) {
  if (void* p = splatkit::spill::allocate(n)) return p;
  if (void* p = allocate_huge(n)) return p;
  for (;;) {
    if (void* p = std::malloc(n ? n : 1)) return p;
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void* allocate_aligned(std::size_t n, std::align_val_t al) {
  const auto alignment = static_cast<std::size_t>(al);
  if (alignment <= 4096)  // arena blocks are page-aligned
    if (void* p = splatkit::spill::allocate(n)) return p;
  if (alignment <= kHugePage)
    if (void* p = allocate_huge(n)) return p;
  for (;;) {
    void* p = nullptr;
    if (::posix_memalign(&p, std::max(alignment, sizeof(void*)), n ? n : 1) == 0) return p;
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void deallocate(void* p) noexcept {
  if (p && !splatkit::spill::release(p)) std::free(p);
}

}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, std::align_val_t al) { return allocate_aligned(n, al); }
void* operator new[](std::size_t n, std::align_val_t al) { return allocate_aligned(n, al); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}

void operator delete(void* p) noexcept { deallocate(p); }
void operator delete[](void* p) noexcept { deallocate(p); }
void operator delete(void* p, std::size_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::size_t) noexcept { deallocate(p); }
void operator delete(void* p, std::align_val_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::align_val_t) noexcept { deallocate(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { deallocate(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { deallocate(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { deallocate(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { deallocate(p); }
