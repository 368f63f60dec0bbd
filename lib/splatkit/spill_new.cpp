// The replaceable global allocation functions of an executable that may spill (spill_arena.h):
// blocks of spill::kMinBlock bytes and more come from the arena once it is started; everything
// else, and everything before it starts, from malloc. Linked into the executables as an object
// (not from an archive, where the C++ runtime's definitions could win), and left out of sanitizer
// builds, whose runtime replaces these functions itself.
#include <algorithm>
#include <cstdlib>
#include <new>

#include "splatkit/spill_arena.h"

namespace {

void* allocate(std::size_t n) {
  if (void* p = splatkit::spill::allocate(n)) return p;
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
